// What a light can contribute at a point, bounded from its extent, power and emission cone: the
// importance by which next-event estimation chooses among a scene's lights at each vertex
// (LightSet::choose). This is pbrt-v4's LightBounds::Importance (Conty Estevez and Kulla, "Importance
// Sampling of Many Lights with Adaptive Tree Splitting", 2018, as pbrt-v4 writes it), with the
// emitter bounded by a sphere rather than a box, and the squared distance clamped to that sphere's
// squared radius (pbrt-v4 clamps it to half the box's diagonal, a length).
//
// The bound is conservative: a light gets importance 0 only where it cannot light the point (the
// point lies outside every direction of its emission cone widened by its extent), so choosing by
// it keeps next-event estimation unbiased.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/trig.h"
#include "core/vec.h"

namespace penumbra {

struct LightBounds {
    Vec3f center;           // of a sphere that bounds the emitter
    float radius = 0;       // 0 for point and spot lights
    Vec3f axis{0, 0, 1};    // the emission cone's axis: a triangle's front normal, a spot light's direction
    float phi = 0;          // power (luminance), the importance's scale
    float cosThetaO = -1;   // cosine of the normals' spread about the axis (-1: all directions)
    float cosThetaE = 0;    // cosine of the emission's angle beyond the normals' spread (0: a hemisphere)
    bool twoSided = false;  // emits about -axis too

    // The importance at a point `p` whose surface normal is `n` (any orientation; a zero vector
    // for a point in a medium).
    float importance(Vec3f p, Vec3f n) const { return importance(p, n, radius * radius); }
    // The same with the squared distance clamped below at `nearestDistanceSquared` instead of the
    // squared radius: a node of many lights (lights/light_tree.h), where p inside the sphere may
    // lie much nearer to some of them than the radius.
    float importance(Vec3f p, Vec3f n, float nearestDistanceSquared) const;
};

// Bounds of two lights together (a node of lights/light_tree.h): the sphere that holds both
// spheres, the cone that holds both cones of normals (pbrt-v4's DirectionCone::Union), the wider
// emission angle, the summed power. Widened by a little more than rounding. Bounds of power 0
// are empty: the union is the other one.
LightBounds unionOf(const LightBounds& a, const LightBounds& b);

namespace detail {

// The importance, one light's fields as plain numbers, written without branches so that a loop
// over lights (LightBoundsBatch) computes several lanes at once; a lane's result is the same bits
// as one call (IEEE operations, in the same order).
inline float lightImportance(float px, float py, float pz, float nx, float ny, float nz, float centerX,
                             float centerY, float centerZ, float radius, float radiusSquared, float axisX,
                             float axisY, float axisZ, float phi, float cosThetaO, float sinThetaO,
                             float cosThetaE, float twoSided, float nearestDistanceSquared) {
    const float dx = px - centerX, dy = py - centerY, dz = pz - centerZ;
    const float distanceSquared = dx * dx + dy * dy + dz * dz;
    // Every operation is done in every lane (no division by zero to avoid); a point at the light's
    // centre (a point light's position) gets w = 0, where every direction is as good as another.
    const float clampedDistanceSquared = std::max(distanceSquared, 1e-30f);
    const float inverseDistance = 1.0f / std::sqrt(clampedDistanceSquared);
    const float wx = dx * inverseDistance, wy = dy * inverseDistance, wz = dz * inverseDistance;
    const float cosThetaWSigned = axisX * wx + axisY * wy + axisZ * wz;
    const float cosThetaW = twoSided != 0.0f ? std::abs(cosThetaWSigned) : cosThetaWSigned;
    const float sinThetaW = safeSqrt(1.0f - cosThetaW * cosThetaW);
    // The directions from p that the bounding sphere subtends: all of them from inside it.
    // Outside, sin(theta_b) = r / d.
    const bool inside = distanceSquared <= radiusSquared;
    const float sinThetaBOutside = radius * inverseDistance;
    const float cosThetaB = inside ? -1.0f : safeSqrt(1.0f - sinThetaBOutside * sinThetaBOutside);
    const float sinThetaB = inside ? 0.0f : sinThetaBOutside;
    // theta' = max(0, theta_w - theta_o - theta_b): the smallest angle between the axis and a
    // direction from the light to p that the extent allows (cos and sin of clamped differences).
    const bool withinSpread = cosThetaW > cosThetaO;
    const float cosThetaX = withinSpread ? 1.0f : cosThetaW * cosThetaO + sinThetaW * sinThetaO;
    const float sinThetaX = withinSpread ? 0.0f : sinThetaW * cosThetaO - cosThetaW * sinThetaO;
    const float cosThetaP = cosThetaX > cosThetaB ? 1.0f : cosThetaX * cosThetaB + sinThetaX * sinThetaB;
    // The cosine at p, at its largest over the directions the light subtends; 1 without a normal.
    const float cosThetaI = std::abs(wx * nx + wy * ny + wz * nz);
    const float sinThetaI = safeSqrt(1.0f - cosThetaI * cosThetaI);
    const bool hasNormal = (nx != 0.0f) | (ny != 0.0f) | (nz != 0.0f);
    const float cosThetaIPWithin = cosThetaI * cosThetaB + sinThetaI * sinThetaB;
    const float cosThetaIP = !hasNormal || cosThetaI > cosThetaB ? 1.0f : cosThetaIPWithin;
    const float importance =
        phi * cosThetaP / std::max(clampedDistanceSquared, nearestDistanceSquared) * cosThetaIP;
    return cosThetaP <= cosThetaE ? 0.0f : std::max(importance, 0.0f);
}

}  // namespace detail

inline float LightBounds::importance(Vec3f p, Vec3f n, float nearestDistanceSquared) const {
    return detail::lightImportance(p.x, p.y, p.z, n.x, n.y, n.z, center.x, center.y, center.z, radius,
                                   radius * radius, axis.x, axis.y, axis.z, phi, cosThetaO,
                                   safeSqrt(1.0f - cosThetaO * cosThetaO), cosThetaE, twoSided ? 1.0f : 0.0f,
                                   nearestDistanceSquared);
}

// The bounds of up to Capacity lights, a field per array, for the importances of all of them at
// one point, computed several at a time (SIMD lanes). Instantiated for 16 (LightSet's choice among
// few emitters) and 8 (a light tree's node: lights/light_tree.h).
template <size_t Capacity>
class LightBoundsBatchOf {
public:
    static constexpr size_t kCapacity = Capacity;
    static constexpr size_t kLanes = 8;  // AVX
    static_assert(Capacity % kLanes == 0);

    // Bounds `b` in slot `i` (< kCapacity), its squared distance clamped below at
    // `nearestDistanceSquared` (LightBounds::importance; by default the squared radius).
    // importances() computes the slots up to the last one set; the caller sets every slot it reads.
    void set(size_t i, const LightBounds& b) { set(i, b, b.radius * b.radius); }
    void set(size_t i, const LightBounds& b, float nearestDistanceSquared);
    // out[i] = bounds i's importance at (p, n), for the slots up to the last one set, rounded up
    // to a multiple of kLanes (out has room for kCapacity).
    void importances(Vec3f p, Vec3f n, float* out) const;

private:
    alignas(32) float centerX_[kCapacity] = {}, centerY_[kCapacity] = {}, centerZ_[kCapacity] = {};
    alignas(32) float radius_[kCapacity] = {}, radiusSquared_[kCapacity] = {};
    alignas(32) float nearestDistanceSquared_[kCapacity] = {};
    alignas(32) float axisX_[kCapacity] = {}, axisY_[kCapacity] = {}, axisZ_[kCapacity] = {};
    alignas(32) float phi_[kCapacity] = {};
    alignas(32) float cosThetaO_[kCapacity] = {}, sinThetaO_[kCapacity] = {}, cosThetaE_[kCapacity] = {};
    alignas(32) float twoSided_[kCapacity] = {};
    size_t used_ = 0;  // slots computed: the last one set, rounded up to kLanes
};

using LightBoundsBatch = LightBoundsBatchOf<16>;
extern template class LightBoundsBatchOf<8>;
extern template class LightBoundsBatchOf<16>;

}  // namespace penumbra
