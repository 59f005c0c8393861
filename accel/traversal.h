// The traversal contract that both backends meet: Embree (the default, accel/embree_accelerator.h)
// and our own BVH (accel/bvh_accelerator.h). A backend answers where a ray first hits the scene and
// whether a segment is blocked; turning a hit into a shading point is shared code
// (geometry/surface_interaction.h), so both backends shade identically. The integrator and the
// render loop are templates over the backend, so that the per-ray calls are direct.
#pragma once

#include <concepts>
#include <cstdint>
#include <string_view>

#include "core/ray.h"
#include "geometry/hit.h"

namespace penumbra {

enum class AcceleratorKind : uint8_t { Embree, Bvh };

// As `--accel` spells it and film files record it.
constexpr std::string_view acceleratorKindName(AcceleratorKind kind) {
    return kind == AcceleratorKind::Bvh ? "bvh" : "embree";
}

// Hit ids follow SceneGeometry's rule (geometry/scene_geometry.h).
//   intersect(ray, hit): the closest hit with tnear <= t <= tfar; false when the ray escapes.
//   occluded(ray): whether anything lies on the ray within [tnear, tfar].
//   intersect(ray, hit, left), occluded(ray, left): the same for a ray leaving triangle `left`
//     (geometry/hit.h), which may be skipped: a backend whose triangle test rejects hits within
//     its own error bound on t (our BVH) needs no such help; Embree's test has no such bound.
//   kName: as `--accel` spells it.
//   kPacketSize: how many coherent rays intersectPacket(rays, count, hits, found) traces at once
//     (1: the backend has no packet kernel and intersectPacket is not called).
//   kReportsCanonicalHits: whether hits already carry the t and barycentrics that
//     canonicalizeHit would compute, so the integrator need not redo them.
template <typename T>
concept TraversalBackend = requires(const T& backend, const Ray& ray, Hit& hit) {
    { backend.intersect(ray, hit) } -> std::same_as<bool>;
    { backend.occluded(ray) } -> std::same_as<bool>;
    { backend.intersect(ray, hit, TriangleLeft{}) } -> std::same_as<bool>;
    { backend.occluded(ray, TriangleLeft{}) } -> std::same_as<bool>;
    { T::kName } -> std::convertible_to<std::string_view>;
    { T::kPacketSize } -> std::convertible_to<int>;
    { T::kReportsCanonicalHits } -> std::convertible_to<bool>;
};

}  // namespace penumbra
