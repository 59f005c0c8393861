// The footprint of a pixel on a surface, for choosing a texture's MIP level: pbrt-v4's
// camera-approximated ray differentials (Camera::Approximate_dp_dxy). At any path vertex, the
// footprint is that of a camera ray from the lens centre to the point and its neighbours one pixel
// over, intersected with the surface's tangent plane, scaled down by sqrt(samples per pixel) (at
// most to 1/8): the pixel filter averages the samples. A cheaper stand-in for tracked ray
// differentials (Igehy 1999): it ignores the lens aperture (as pbrt-v4 does), camera motion and
// the spreading of the footprint by curved reflectors after the first bounce.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec.h"

namespace penumbra {

// Where a texture is looked up, and how fast (u, v) changes from one pixel to the next.
struct TextureQuery {
    Vec2f uv;
    Vec3f p{0.0f, 0.0f, 0.0f}, n{0.0f, 0.0f, 0.0f};  // the point and geometric normal (world space)
    float dudx = 0.0f, dvdx = 0.0f, dudy = 0.0f, dvdy = 0.0f;
    Vec3f dpdx{0.0f, 0.0f, 0.0f}, dpdy{0.0f, 0.0f, 0.0f};  // the point's footprint (for mapped textures)
};

// The camera as the footprint needs it: the lens centre, the image's right and up axes (unit), the
// angular spacing of pixels at the image centre, and the sample-count scale. An orthographic
// camera's rays are parallel: then `parallelDirection` is their direction and pixelSpacing the
// distance between neighbouring rays.
struct CameraFootprint {
    Vec3f origin;
    Vec3f right, up;
    float pixelSpacing = 0.0f;  // distance between neighbouring pixels on the image plane at distance 1
    float sampleScale = 1.0f;   // max(1/8, 1 / sqrt(spp))
    Vec3f parallelDirection{0.0f, 0.0f, 0.0f};  // zero unless the rays are parallel
};

// The query at point p (normal n, uv) of a surface with partial derivatives dpdu, dpdv.
inline TextureQuery textureQueryAt(const CameraFootprint& camera, Vec3f p, Vec3f n, Vec2f uv, Vec3f dpdu,
                                   Vec3f dpdv) {
    TextureQuery query;
    query.uv = uv;
    query.p = p;
    query.n = n;
    const Vec3f toPoint = p - camera.origin;
    const float distance = length(toPoint);
    const bool parallel = lengthSquared(camera.parallelDirection) > 0.0f;
    if (!(distance > 0.0f) && !parallel) return query;
    const Vec3f forward = parallel ? camera.parallelDirection : toPoint / distance;
    const float planeOffset = dot(n, toPoint);
    // The neighbouring rays, and where they meet the tangent plane: turned by the pixel spacing
    // from the lens centre, or displaced by it along the parallel direction.
    auto offsetOnPlane = [&](Vec3f axis) {
        const Vec3f direction = parallel ? forward : forward + axis * camera.pixelSpacing;
        const float cosine = dot(n, direction);
        if (!(std::abs(cosine) > 1e-6f)) return Vec3f{0.0f, 0.0f, 0.0f};
        if (parallel) {
            const Vec3f start = axis * camera.pixelSpacing;  // relative to p
            return (start - direction * (dot(n, start) / cosine)) * camera.sampleScale;
        }
        const Vec3f hit = camera.origin + direction * (planeOffset / cosine);
        return (hit - p) * camera.sampleScale;
    };
    const Vec3f dpdx = offsetOnPlane(camera.right), dpdy = offsetOnPlane(camera.up);
    query.dpdx = dpdx;
    query.dpdy = dpdy;
    // Least squares for (du, dv) with dpdu du + dpdv dv = dp (pbrt-v4's ComputeDifferentials).
    const float ata00 = dot(dpdu, dpdu), ata01 = dot(dpdu, dpdv), ata11 = dot(dpdv, dpdv);
    float invDet = 1.0f / (ata00 * ata11 - ata01 * ata01);
    if (!std::isfinite(invDet)) invDet = 0.0f;
    const float atb0x = dot(dpdu, dpdx), atb1x = dot(dpdv, dpdx);
    const float atb0y = dot(dpdu, dpdy), atb1y = dot(dpdv, dpdy);
    auto clampFinite = [](float x) { return std::isfinite(x) ? std::clamp(x, -1e8f, 1e8f) : 0.0f; };
    query.dudx = clampFinite((ata11 * atb0x - ata01 * atb1x) * invDet);
    query.dvdx = clampFinite((ata00 * atb1x - ata01 * atb0x) * invDet);
    query.dudy = clampFinite((ata11 * atb0y - ata01 * atb1y) * invDet);
    query.dvdy = clampFinite((ata00 * atb1y - ata01 * atb0y) * invDet);
    return query;
}

}  // namespace penumbra
