// The Embree backend: every Embree call of penumbra lives in embree_accelerator.cpp.
#pragma once

#include <embree3/rtcore.h>

#include <vector>

#include "scenes/accelerator.h"

namespace penumbra {

struct EmbreeOptions {
    // RTC_SCENE_FLAG_ROBUST: watertight traversal, no ray slips through a shared edge (see
    // RenderSettings::watertight). Off, traversal is about a quarter faster.
    bool robust = true;
};

class EmbreeAccelerator final : public Accelerator {
public:
    explicit EmbreeAccelerator(const Scene& scene, EmbreeOptions options = {});
    ~EmbreeAccelerator() override;
    EmbreeAccelerator(const EmbreeAccelerator&) = delete;
    EmbreeAccelerator& operator=(const EmbreeAccelerator&) = delete;

    std::string_view name() const override { return "embree"; }
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<RTCScene> instancedScenes_;  // one per moving object, released with the backend
    uint32_t sphereGeomId_ = 0;              // == meshes.size(): all static spheres
    std::vector<uint32_t> movingSphereOfGeomId_;  // geomId - sphereGeomId_ - 1 -> sphere index
};

}  // namespace penumbra
