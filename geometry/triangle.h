// A triangle's maths: the ray test both backends' hits are recomputed with, and the sampling of a
// point on it (its area lights, lights/triangle_light.h). Its shading point is made with the other
// shapes' in geometry/surface_interaction.h.
//
// The ray test: watertight ray/triangle intersection, Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection" (Journal of Computer Graphics Techniques 2(1), 2013), in the form of pbrt-v4
// (Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th ed., section 6.5.3).
//
// The ray is made the +z axis of a sheared coordinate system; the triangle's 2D edge functions
// about the origin then decide the hit. A shared edge gets the same edge function (negated) in
// both of its triangles, so a ray through it is never missed by both. When an edge function
// rounds to exactly zero it is recomputed in double precision, where the products of floats are
// exact, so its sign is right. This needs a*b - c*d to be evaluated without contraction into a
// fused multiply-add (an FMA would make the two triangles' values differ): the file that includes
// this one is compiled with -ffp-contract=off.
//
// A hit is accepted only when t exceeds the bound on t's rounding error of pbrt-v4 (section
// 6.8.7): within it the hit may be the surface the ray starts on, offset by core/ray_offset.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/check.h"
#include "core/float_error.h"
#include "core/sampling.h"
#include "core/vec.h"

namespace penumbra {

// What the test needs of a ray, computed once per ray: the axis along which the direction is
// largest (kz, after a permutation) and the shear that maps the direction to +z.
struct WatertightRay {
    int kx = 0, ky = 1, kz = 2;
    float ox = 0, oy = 0, oz = 0;  // origin, permuted
    float sx = 0, sy = 0, sz = 1;

    WatertightRay() = default;
    WatertightRay(Vec3f origin, Vec3f direction) {
        const Vec3f a = abs(direction);
        kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
        kx = kz == 2 ? 0 : kz + 1;
        ky = kx == 2 ? 0 : kx + 1;
        ox = origin[kx];
        oy = origin[ky];
        oz = origin[kz];
        const float dz = direction[kz];
        sx = -direction[kx] / dz;
        sy = -direction[ky] / dz;
        sz = 1.0f / dz;
    }
};

// pbrt-v4's bound on the absolute error of t: maxXt, maxYt are the largest magnitudes of the
// triangle's sheared x and y, maxZ that of its unscaled z (relative to the origin), maxZt that of
// z * sz, maxE that of the edge functions. pbrt bounds the error of x + sx z with the scaled z,
// which is wrong by the factor |direction| and lost hits of unnormalized rays at small scales;
// |sx|, |sy| <= 1 (z is the dominant axis), so the unscaled maxZ bounds |sx z| and |sy z|.
inline float watertightTError(float maxXt, float maxYt, float maxZ, float maxZt, float maxE, float invDet) {
    const float deltaZ = gamma(3) * maxZt;
    const float deltaX = gamma(5) * (maxXt + maxZ);
    const float deltaY = gamma(5) * (maxYt + maxZ);
    const float deltaE = 2.0f * (gamma(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    return 3.0f * (gamma(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::abs(invDet);
}

// A triangle's vertices (nine floats: p0, p1, p2) relative to the ray origin, permuted so the
// ray runs along z, then sheared so it runs along +z; z is left unscaled (times r.sz it is the
// scaled depth).
struct ShearedTriangle {
    float x0, y0, z0, x1, y1, z1, x2, y2, z2;
};
[[gnu::always_inline]] inline ShearedTriangle shearedVertices(const WatertightRay& r, const float* vertices) {
    const float* v0 = vertices;
    const float* v1 = vertices + 3;
    const float* v2 = vertices + 6;
    const float z0 = v0[r.kz] - r.oz, z1 = v1[r.kz] - r.oz, z2 = v2[r.kz] - r.oz;
    return {(v0[r.kx] - r.ox) + r.sx * z0, (v0[r.ky] - r.oy) + r.sy * z0, z0,
            (v1[r.kx] - r.ox) + r.sx * z1, (v1[r.ky] - r.oy) + r.sy * z1, z1,
            (v2[r.kx] - r.ox) + r.sx * z2, (v2[r.ky] - r.oy) + r.sy * z2, z2};
}

struct TriangleHit {
    float t = 0.0f;
    float b1 = 0.0f, b2 = 0.0f;  // barycentrics of vertices 1 and 2
};

// `vertices` holds p0, p1, p2 as nine floats. True when tMin <= t <= tMax and t exceeds its error
// bound.
inline bool intersectTriangleWatertight(const WatertightRay& r, const float* vertices, float tMin, float tMax,
                                        TriangleHit& hit) {
    const auto [x0, y0, z0, x1, y1, z1, x2, y2, z2] = shearedVertices(r, vertices);

    // Edge functions; e_i is twice the signed area of the sub-triangle opposite vertex i.
    float e0 = x1 * y2 - y1 * x2;
    float e1 = x2 * y0 - y2 * x0;
    float e2 = x0 * y1 - y0 * x1;
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) [[unlikely]] {
        e0 = float(double(x1) * double(y2) - double(y1) * double(x2));
        e1 = float(double(x2) * double(y0) - double(y2) * double(x0));
        e2 = float(double(x0) * double(y1) - double(y0) * double(x1));
    }
    // The origin must be inside all three edges (either orientation: no back-face culling).
    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return false;
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return false;

    // Interpolated, scaled depth; reject hits behind the origin before dividing.
    const float tScaled = e0 * (z0 * r.sz) + e1 * (z1 * r.sz) + e2 * (z2 * r.sz);
    if (det < 0.0f ? tScaled > 0.0f : tScaled < 0.0f) return false;
    const float invDet = 1.0f / det;
    const float t = tScaled * invDet;
    if (!(t >= tMin && t <= tMax)) return false;  // also rejects NaN
    const float maxXt = std::max({std::abs(x0), std::abs(x1), std::abs(x2)});
    const float maxYt = std::max({std::abs(y0), std::abs(y1), std::abs(y2)});
    const float maxZ = std::max({std::abs(z0), std::abs(z1), std::abs(z2)});
    const float maxZt = std::max({std::abs(z0 * r.sz), std::abs(z1 * r.sz), std::abs(z2 * r.sz)});
    const float maxE = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
    if (t <= watertightTError(maxXt, maxYt, maxZ, maxZt, maxE, invDet)) return false;
    hit.t = t;
    hit.b1 = e1 * invDet;
    hit.b2 = e2 * invDet;
    // e0, e1, e2 have det's sign: the barycentrics lie in [0, 1] and sum to at most 1, up to the
    // roundings of det and of the two quotients.
    PENUMBRA_CHECK(hit.b1 >= 0.0f && hit.b2 >= 0.0f && hit.b1 + hit.b2 <= 1.0f + 1e-6f,
                   "a triangle hit's barycentrics lie in the triangle");
    return true;
}

// The bound intersectTriangleWatertight compares t with, for a ray and triangle whatever the test
// says (for tools that explain why a hit was rejected); infinity when the triangle is degenerate
// in the ray's projection.
inline float watertightTErrorBound(const WatertightRay& r, const float* vertices) {
    const auto [x0, y0, z0, x1, y1, z1, x2, y2, z2] = shearedVertices(r, vertices);
    const float e0 = x1 * y2 - y1 * x2, e1 = x2 * y0 - y2 * x0, e2 = x0 * y1 - y0 * x1;
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return std::numeric_limits<float>::infinity();
    const float maxXt = std::max({std::abs(x0), std::abs(x1), std::abs(x2)});
    const float maxYt = std::max({std::abs(y0), std::abs(y1), std::abs(y2)});
    const float maxZ = std::max({std::abs(z0), std::abs(z1), std::abs(z2)});
    const float maxZt = std::max({std::abs(z0 * r.sz), std::abs(z1 * r.sz), std::abs(z2 * r.sz)});
    const float maxE = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
    return watertightTError(maxXt, maxYt, maxZ, maxZt, maxE, 1.0f / det);
}

// A point of the triangle (p0, p1, p2) uniformly by area (u in [0, 1)^2), with its barycentric
// coordinates (b.x of p1, b.y of p2) and the bound on its rounding error, as for a hit's
// barycentric interpolation (geometry/surface_interaction.h).
struct TrianglePointSample {
    Vec3f point;
    Vec3f pointError;
    Vec2f barycentrics;
};
[[gnu::always_inline]] inline TrianglePointSample sampleTriangle(Vec3f p0, Vec3f p1, Vec3f p2, Vec2f u) {
    const Vec2f b = sampleUniformTriangle(u);
    return {p0 * (1.0f - b.x - b.y) + p1 * b.x + p2 * b.y,
            (abs(p0 * (1.0f - b.x - b.y)) + abs(p1 * b.x) + abs(p2 * b.y)) * gamma(7), b};
}

}  // namespace penumbra
