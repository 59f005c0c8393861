// Warps from the unit square to the domains the renderer samples, with their densities.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/trig.h"
#include "core/vec.h"

namespace penumbra {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;

// Shirley-Chiu concentric map: uniform on the unit disk, low distortion (keeps stratification).
[[gnu::always_inline]] inline Vec2f sampleUniformDiskConcentric(Vec2f u) {
    const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    if (ox == 0.0f && oy == 0.0f) return {0.0f, 0.0f};
    // theta = (pi/4)(oy/ox), or pi/2 - (pi/4)(ox/oy) whose cosine and sine are those of
    // (pi/4)(ox/oy) swapped: either way an angle in [-pi/4, pi/4].
    if (std::abs(ox) > std::abs(oy)) {
        const Vec2f cs = cosSinQuarterPi((kPi / 4.0f) * (oy / ox));
        return {ox * cs.x, ox * cs.y};
    }
    const Vec2f cs = cosSinQuarterPi((kPi / 4.0f) * (ox / oy));
    return {oy * cs.y, oy * cs.x};
}

// Cosine-weighted direction on the +z hemisphere (Malley's method); pdf = cos(theta) / pi. It and
// the disk map (with its sine and cosine) are always inlined: with several materials calling them the
// compiler stopped inlining them into Lambert's sampling in the integrator (bench/README.md, "Speed tricks").
[[gnu::always_inline]] inline Vec3f sampleCosineHemisphere(Vec2f u) {
    const Vec2f d = sampleUniformDiskConcentric(u);
    const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0.0f ? cosTheta * kInvPi : 0.0f; }

inline Vec3f sampleUniformSphere(Vec2f u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const Vec2f azimuth = cosSinTurn(u.y);
    return {r * azimuth.x, r * azimuth.y, z};
}
inline constexpr float uniformSpherePdf() { return 1.0f / (4.0f * kPi); }

// Uniform direction in the cone around +z with cos(half-angle) = cosThetaMax.
inline Vec3f sampleUniformCone(Vec2f u, float cosThetaMax) {
    const float cosTheta = (1.0f - u.x) + u.x * cosThetaMax;
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const Vec2f azimuth = cosSinTurn(u.y);
    return {sinTheta * azimuth.x, sinTheta * azimuth.y, cosTheta};
}
inline float uniformConePdf(float cosThetaMax) { return 1.0f / (2.0f * kPi * (1.0f - cosThetaMax)); }

// Uniform barycentrics (b1, b2) on a triangle; b0 = 1 - b1 - b2. Heitz's low-distortion mapping
// ("A Low-Distortion Map Between Triangle and Square", 2019), which keeps strata compact.
// Below the diagonal (x < y) the map is b0 = x / 2, b1 = y - x / 2, above it b0 = x - y / 2,
// b1 = y / 2: both are "half the smaller coordinate taken off each" (x - x / 2 is x / 2 exactly), so
// there is no branch on which side u lies, a coin toss a branch predictor misses half the time
// (bench/README.md, "Speed tricks").
inline Vec2f sampleUniformTriangle(Vec2f u) {
    const float offset = std::min(u.x, u.y) * 0.5f;
    return {u.x - offset, u.y - offset};
}

// A density of 1 / area over a surface, turned into one per solid angle at a point
// `distanceSquared` away whose direction makes the cosine `cosAtSurface` (>= 0) with the surface;
// 0 where there is none.
inline float areaToSolidAnglePdf(float distanceSquared, float cosAtSurface, float area) {
    return (area > 0.0f && cosAtSurface > 0.0f) ? distanceSquared / (cosAtSurface * area) : 0.0f;
}

// Tent (triangle) filter of the given radius, sampled by inverting its CDF; used for filter
// importance sampling, so every sample has weight 1.
inline float sampleTent(float u, float radius) {
    if (u < 0.5f) return radius * (std::sqrt(2.0f * u) - 1.0f);
    return radius * (1.0f - std::sqrt(2.0f - 2.0f * u));
}

// Veach's power heuristic with beta = 2, in double so that squares of very large or very small
// densities neither overflow nor vanish.
inline float powerHeuristic(float pdfA, float pdfB) {
    if (std::isinf(pdfA)) return 1.0f;
    const double a = double(pdfA) * pdfA, b = double(pdfB) * pdfB;
    return (a + b) > 0.0 ? float(a / (a + b)) : 0.0f;
}

}  // namespace penumbra
