// The traversal interface that both backends implement: Embree (the default) and our own BVH
// (scenes/bvh_accelerator.h). Backends answer where a ray first hits the scene and whether a
// segment is blocked; turning a hit into a shading point is shared code
// (renderer/surface_interaction.h), so both backends shade identically.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>

#include "core/ray.h"
#include "scenes/scene.h"

namespace penumbra {

// Geometry ids: mesh i of Scene::meshes has geomId i (primId = triangle index); all spheres share
// geomId == Scene::meshes.size() (primId = sphere index).
struct Hit {
    float t = 0.0f;
    float u = 0.0f, v = 0.0f;  // triangle barycentrics of vertices 1 and 2
    Vec3f geometricNormal;     // as the backend reports it: not normalized, orientation unspecified
    uint32_t geomId = 0;
    uint32_t primId = 0;
};

class Accelerator {
public:
    virtual ~Accelerator() = default;
    virtual std::string_view name() const = 0;
    // Closest hit with tnear <= t <= tfar; false when the ray escapes.
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    // True when anything lies on the ray within [tnear, tfar].
    virtual bool occluded(const Ray& ray) const = 0;
};

enum class AcceleratorKind : uint8_t { Embree, Bvh };

std::unique_ptr<Accelerator> makeAccelerator(AcceleratorKind kind, const Scene& scene);

}  // namespace penumbra
