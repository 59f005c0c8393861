// Bilinear patches: quadrilaterals whose four corners need not lie in a plane, the surface
// p(u, v) = lerp(v, lerp(u, p00, p10), lerp(u, p01, p11)) for (u, v) in [0, 1]^2, as pbrt-v4's
// `bilinearmesh` describes them; and the ray test both backends use (our BVH calls it from its
// leaves, Embree from a user geometry), so both find the same hits bit for bit.
//
// The ray test is Reshetov's ("Cool Patches: A Geometric Approach to Ray/Bilinear Patch
// Intersections", Ray Tracing Gems, chapter 8, 2019): a point of the ray lies on the patch where
// it meets the segment between lerp(u, p00, p10) and lerp(u, p01, p11), which is a quadratic in u;
// for each root in [0, 1], v and t follow from the ray's closest approach to that segment. Its
// roots are taken in the stable form (neither the difference of two nearly equal numbers), so a
// flat patch (the quadratic's leading term 0) loses nothing.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/float_error.h"
#include "core/vec.h"
#include "geometry/medium_interface.h"

namespace penumbra {

struct BilinearPatches {
    std::string name;
    std::vector<Vec3f> positions;   // world space; never moving
    std::vector<uint32_t> indices;  // four per patch: p00, p10, p01, p11
    std::vector<Vec3f> normals;     // per vertex, or empty
    std::vector<Vec2f> uvs;         // per vertex, or empty: the patch's own (u, v)
    // The front is where cross(dp/du, dp/dv) points, turned to the side of the vertex normals when
    // there are normals, else reversed when `reversed` (pbrt-v4's ReverseOrientation).
    bool reversed = false;
    uint32_t material = 0;
    MediumInterface media{};

    size_t patchCount() const { return indices.size() / 4; }
    // The positions of patch `patch`'s corners, p00, p10, p01, p11.
    std::array<Vec3f, 4> cornerPositions(size_t patch) const {
        const uint32_t* corner = &indices[4 * patch];
        return {positions[corner[0]], positions[corner[1]], positions[corner[2]], positions[corner[3]]};
    }
};

namespace bilinear {

inline Vec3f lerp(float t, Vec3f a, Vec3f b) { return a * (1.0f - t) + b * t; }
inline Vec2f lerp(float t, Vec2f a, Vec2f b) { return a * (1.0f - t) + b * t; }

// The point p(u, v) of the patch with corners p[0..3] = p00, p10, p01, p11.
inline Vec3f point(const Vec3f* p, float u, float v) {
    return lerp(v, lerp(u, p[0], p[1]), lerp(u, p[2], p[3]));
}
inline Vec3f dpdu(const Vec3f* p, float v) { return lerp(v, p[1] - p[0], p[3] - p[2]); }
inline Vec3f dpdv(const Vec3f* p, float u) { return lerp(u, p[2] - p[0], p[3] - p[1]); }

// The corners' largest magnitude in each coordinate.
inline Vec3f cornerMagnitudes(const Vec3f* p) {
    return max(max(abs(p[0]), abs(p[1])), max(abs(p[2]), abs(p[3])));
}

// A bound on each coordinate's error of point(): three roundings in each of the two levels of
// interpolation, of values at most the corners' largest magnitude (weights in [0, 1]), with slack.
inline Vec3f pointError(const Vec3f* p) { return cornerMagnitudes(p) * gamma(8); }

// The (u, v) at which the bilinear interpolation of q[0..3] (at p00, p10, p01, p11) is `target`:
// Newton's method from the centre (exact after one step when the q form a parallelogram).
inline Vec2f inverse(const Vec2f* q, Vec2f target) {
    Vec2f uv{0.5f, 0.5f};
    for (int iteration = 0; iteration < 6; ++iteration) {
        const Vec2f f = lerp(uv.y, lerp(uv.x, q[0], q[1]), lerp(uv.x, q[2], q[3])) - target;
        const Vec2f du = lerp(uv.y, q[1] - q[0], q[3] - q[2]), dv = lerp(uv.x, q[2] - q[0], q[3] - q[1]);
        const float determinant = du.x * dv.y - du.y * dv.x;
        if (!(std::abs(determinant) > 1e-20f)) break;
        uv.x -= (f.x * dv.y - f.y * dv.x) / determinant;
        uv.y -= (du.x * f.y - du.y * f.x) / determinant;
    }
    return {std::clamp(uv.x, 0.0f, 1.0f), std::clamp(uv.y, 0.0f, 1.0f)};
}

}  // namespace bilinear

struct BilinearPatchHit {
    float t = 0.0f, u = 0.0f, v = 0.0f;
};

// The nearest hit in [tMin, tMax] of the ray origin + t direction with the patch of corners p[0..3]
// (p00, p10, p01, p11); false when there is none. Hits nearer the origin than the coordinates'
// rounding (pbrt-v4's guard) are refused, so a ray leaving the patch does not meet it there again.
inline bool intersectBilinearPatch(const Vec3f* p, Vec3f origin, Vec3f direction, float tMin, float tMax,
                                   BilinearPatchHit& hit) {
    const Vec3f q00 = p[0] - origin, q10 = p[1] - origin;
    const Vec3f e00 = p[2] - p[0];  // along v at u = 0
    const Vec3f e11 = p[3] - p[1];  // along v at u = 1
    // The triple product of (the segment's start at u - origin, direction, the segment at u), zero
    // where the ray meets the segment's line, is a u^2 + b u + c: c at u = 0, a + b + c at u = 1,
    // a from the patch's twist.
    const float a = dot(cross(p[1] - p[0], p[2] - p[3]), direction);
    const float c = dot(cross(q00, direction), e00);
    const float b = dot(cross(q10, direction), e11) - (a + c);
    // b^2 - 4 a c with the product's rounding error recovered by a fused multiply-add (Kahan's).
    const float fourAC = 4.0f * a * c;
    const float discriminant = std::fma(b, b, -fourAC) + std::fma(-4.0f * a, c, fourAC);
    if (!(discriminant >= 0.0f)) return false;
    const float q = -0.5f * (b + std::copysign(std::sqrt(discriminant), b));
    // The stable pair of roots; with a = 0 (a flat patch, or a ray along its twist's axis) only
    // c / q is finite, and with q = 0 too (b = c = 0: the ray within the patch's plane) none is.
    const float roots[2] = {q / a, c / q};
    const float nearest =
        gamma(10) * (maxComponent(abs(origin)) + maxComponent(bilinear::cornerMagnitudes(p)));
    bool found = false;
    float tBest = tMax;
    for (float u : roots) {
        if (!(u >= 0.0f && u <= 1.0f)) continue;
        // The segment at u: from start, along span. The ray's closest approach to its line, by
        // Cramer's rule with perp = direction x span (the common perpendicular).
        const Vec3f start = bilinear::lerp(u, q00, q10);
        const Vec3f span = bilinear::lerp(u, e00, e11);
        const Vec3f perp = cross(direction, span);
        const float perpLength2 = dot(perp, perp);
        if (!(perpLength2 > 0.0f)) continue;
        const Vec3f startPerp = cross(perp, start);
        const float tScaled = dot(startPerp, span);       // t times perpLength2
        const float vScaled = dot(startPerp, direction);  // v times perpLength2
        if (!(vScaled >= 0.0f && vScaled <= perpLength2)) continue;
        const float t = tScaled / perpLength2;
        if (!(t >= tMin && (found ? t < tBest : t <= tBest))) continue;
        if (!(t * length(direction) > nearest)) continue;
        tBest = t;
        hit.t = t;
        hit.u = u;
        hit.v = std::clamp(vScaled / perpLength2, 0.0f, 1.0f);
        found = true;
    }
    return found;
}

}  // namespace penumbra
