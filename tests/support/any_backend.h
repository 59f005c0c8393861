// Either traversal backend behind one virtual interface, so that a parametrised test runs the same
// cases on both. Only tests use it: the renderer calls the backends directly (accel/traversal.h).
#pragma once

#include <memory>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "accel/traversal.h"

namespace penumbra::testing {

class AnyBackend {
public:
    virtual ~AnyBackend() = default;
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    virtual bool occluded(const Ray& ray) const = 0;
};

template <TraversalBackend Backend>
class BackendAdapter final : public AnyBackend {
public:
    explicit BackendAdapter(const SceneGeometry& scene) : backend_(scene) {}
    bool intersect(const Ray& ray, Hit& hit) const override { return backend_.intersect(ray, hit); }
    bool occluded(const Ray& ray) const override { return backend_.occluded(ray); }

private:
    Backend backend_;
};

inline std::unique_ptr<AnyBackend> makeBackend(AcceleratorKind kind, const SceneGeometry& scene) {
    switch (kind) {
        case AcceleratorKind::Embree:
            return std::make_unique<BackendAdapter<EmbreeAccelerator>>(scene);
        case AcceleratorKind::Bvh:
            return std::make_unique<BackendAdapter<BvhAccelerator>>(scene);
    }
    return nullptr;
}

}  // namespace penumbra::testing
