// A material's perturbation of its surface's shading normal, as pbrt-v4's `displacement` (a bump
// map: Blinn 1978) and `normalmap` do it (pbrt-v4's BumpMap and NormalMap, materials.h):
//  - Bump: a height field h(u, v) in scene units along the normal, differentiated by forward
//    differences over half the pixel footprint in (u, v) (du = (|du/dx| + |du/dy|) / 2, or 0.0005
//    without a footprint): dp/du' = dp/du + (h(u + du) - h) / du n, the same in v, and the new normal
//    cross(dp/du', dp/dv'). pbrt-v4 also adds h dn/du for curved shading normals; that term is left
//    out (it vanishes on flat triangles and for small heights).
//  - Normal map: a tangent-space normal, 2 rgb - 1 of a linear image, in the frame of dp/du (x) and
//    the normal (z).
// Either way the result is turned to the geometric normal's side, as pbrt-v4 turns it.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/vec.h"
#include "textures/texture.h"

namespace penumbra {

struct NormalPerturbation {
    enum class Kind : uint8_t { Bump, NormalMap };
    Kind kind = Kind::Bump;
    Texture texture;  // Bump: the height (first channel); NormalMap: the linear RGB image
};

// The shading normal turned by the perturbation at a point whose shading normal is `n` (unit),
// with surface derivatives dp/du and dp/dv, looked up at `query` (uv and its footprint).
inline Vec3f perturbedNormal(const NormalPerturbation& perturbation, const TextureQuery& query, Vec3f n,
                             Vec3f dpdu, Vec3f dpdv, Vec3f geometricNormal) {
    // The shading frame's own tangents: dp/du and dp/dv projected onto the shading normal's plane.
    const Vec3f su = dpdu - n * dot(n, dpdu), sv = dpdv - n * dot(n, dpdv);
    Vec3f turned;
    if (perturbation.kind == NormalPerturbation::Kind::Bump) {
        float du = 0.5f * (std::abs(query.dudx) + std::abs(query.dudy));
        float dv = 0.5f * (std::abs(query.dvdx) + std::abs(query.dvdy));
        if (du == 0.0f) du = 0.0005f;
        if (dv == 0.0f) dv = 0.0005f;
        TextureQuery shifted = query;
        const float height = perturbation.texture.evaluate(query).r;
        // The point moves with (u, v), for textures of the point (pbrt-v4's BumpMap).
        shifted.uv = {query.uv.x + du, query.uv.y};
        shifted.p = query.p + dpdu * du;
        const float heightU = perturbation.texture.evaluate(shifted).r;
        shifted.uv = {query.uv.x, query.uv.y + dv};
        shifted.p = query.p + dpdv * dv;
        const float heightV = perturbation.texture.evaluate(shifted).r;
        turned = cross(su + n * ((heightU - height) / du), sv + n * ((heightV - height) / dv));
    } else {
        const Rgb rgb = perturbation.texture.evaluate(query);
        const Vec3f local{2.0f * rgb.r - 1.0f, 2.0f * rgb.g - 1.0f, 2.0f * rgb.b - 1.0f};
        const Vec3f x = lengthSquared(su) > 0.0f ? normalize(su) : Vec3f{0.0f, 0.0f, 0.0f};
        turned = x * local.x + cross(n, x) * local.y + n * local.z;
    }
    const float length2 = lengthSquared(turned);
    if (!(length2 > 0.0f) || !std::isfinite(length2)) return n;  // degenerate: keep the normal
    turned = turned / std::sqrt(length2);
    return dot(turned, geometricNormal) < 0.0f ? -turned : turned;
}

}  // namespace penumbra
