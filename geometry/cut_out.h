// Cut-outs: a shape's "alpha" (pbrt-v4's), its coverage over the surface, a constant or a texture
// read by Texture::coverage. Where alpha is 1 the surface is there, where it is 0 rays pass
// through it, and in between a ray's hit is kept with probability alpha: the stochastic test of
// pbrt-v4 (GeometricPrimitive::Intersect), so that a half-covered leaf stops half of the camera,
// bounce and shadow rays that meet it and the image is the covered fraction's in expectation. The
// exact alternative, continuing the path through the surface with weight 1 - alpha, would need
// the integrator to carry a partial hit: the test lives in the traversal of both backends
// instead (Embree's filter functions, our BVH's triangle test), for every kind of ray.
//
// The test's number comes from a hash of the world-space ray (its origin and direction as the
// integrator traces it) and the hit's scene ids, so both backends decide alike for the same ray and
// triangle; the ids make two cut-outs along one ray decide independently (pbrt-v4 gets this by
// tracing a new ray from each hit it ignores). The backends compute the barycentrics of a hit with
// different tests, so where the coverage changes between two neighbouring points (a texel's edge
// of a bilinear image) the two may see values a rounding apart, and decide differently when the
// ray's number falls between them: tools/crosscheck.h counts those.
#pragma once

#include <bit>
#include <cstdint>

#include "core/hash.h"
#include "core/ray.h"
#include "geometry/triangle_mesh.h"

namespace penumbra {

// The part of the test's number that depends on the ray alone, hashed once per traced ray.
inline uint64_t cutOutRayHash(const Ray& ray) {
    return hashWords(std::bit_cast<uint32_t>(ray.origin.x), std::bit_cast<uint32_t>(ray.origin.y),
                     std::bit_cast<uint32_t>(ray.origin.z), std::bit_cast<uint32_t>(ray.direction.x),
                     std::bit_cast<uint32_t>(ray.direction.y), std::bit_cast<uint32_t>(ray.direction.z));
}

// Whether a hit on a surface of coverage `alpha` is kept: always at 1 or more, never at 0 or less
// (or NaN), else when the number of (ray, geomId, primId), uniform in [0, 1), is below alpha.
// `geomId` is the scene's id of the shape hit (the instance's for an instance), `primId` the triangle.
inline bool keepsCutOutHit(float alpha, uint64_t rayHash, uint32_t geomId, uint32_t primId) {
    if (alpha >= 1.0f) return true;
    if (!(alpha > 0.0f)) return false;
    const uint64_t h = hashCombine(hashCombine(rayHash, geomId), primId);
    return bitsToUnitFloat(uint32_t(h >> 32)) < alpha;
}

// A cut-out's coverage at `uv`, looked up without a footprint (the finest level), as an emitter's
// texture is: the same value for the same point whatever ray meets it.
inline float cutOutCoverage(const Texture& alpha, Vec2f uv) {
    TextureQuery query;
    query.uv = uv;
    return alpha.coverage(query);
}

}  // namespace penumbra
