// How a 2D texture finds its coordinates (s, t) at a shading point (pbrt-v4's TextureMapping2D):
// the surface's (u, v) (the default), or the point itself in the texture's own space: spherical
// (s = theta / pi, t = phi / 2 pi of the direction from the space's origin, theta from its +z),
// cylindrical (s = (pi + atan2(y, x)) / 2 pi around its z axis, t = z) or planar (s = p . v1,
// t = p . v2). Then (s, t) * uvScale + uvOffset (textures/texture.h). With the coordinates, their
// changes from one pixel to the next, for choosing an image's MIP level: for (u, v) the query's, for
// the others the derivatives of (s, t) along the point's own footprint (TextureQuery::dpdx, dpdy;
// pbrt-v4's, but for its spherical mapping whose two derivatives are swapped against its (s, t)).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/transform.h"
#include "core/vec.h"
#include "textures/texture_footprint.h"

namespace penumbra {

// Texture coordinates and their derivatives across the pixel footprint.
struct TextureCoordinates {
    Vec2f st;
    float dsdx = 0.0f, dsdy = 0.0f, dtdx = 0.0f, dtdy = 0.0f;
};

enum class TextureMappingKind : uint8_t { Uv, Spherical, Cylindrical, Planar };

struct TextureMapping {
    TextureMappingKind kind = TextureMappingKind::Uv;
    Transform worldToTexture;    // the texture's space (not Uv)
    Vec3f v1{1.0f, 0.0f, 0.0f};  // Planar: the texture space's directions of s and t
    Vec3f v2{0.0f, 1.0f, 0.0f};

    // The query's (s, t) and derivatives, before uvScale and uvOffset.
    TextureCoordinates map(const TextureQuery& query) const {
        if (kind == TextureMappingKind::Uv) return {query.uv, query.dudx, query.dudy, query.dvdx, query.dvdy};
        const Vec3f p = worldToTexture.applyPoint(query.p);
        const Vec3f dpdx = worldToTexture.applyVector(query.dpdx),
                    dpdy = worldToTexture.applyVector(query.dpdy);
        Vec3f dsdp, dtdp;
        TextureCoordinates c;
        constexpr float kPi = std::numbers::pi_v<float>, kInvPi = std::numbers::inv_pi_v<float>,
                        kInv2Pi = 0.5f * kInvPi;
        const float x2y2 = p.x * p.x + p.y * p.y;
        switch (kind) {
            case TextureMappingKind::Spherical: {
                const float r = std::sqrt(x2y2 + p.z * p.z);
                const float cosTheta = r > 0.0f ? std::clamp(p.z / r, -1.0f, 1.0f) : 1.0f;
                const float phi = std::atan2(p.y, p.x);
                c.st = {std::acos(cosTheta) * kInvPi, (phi < 0.0f ? phi + 2.0f * kPi : phi) * kInv2Pi};
                // d theta / dp and d phi / dp.
                const float rxy = std::sqrt(x2y2);
                if (rxy > 0.0f && r > 0.0f) {
                    dsdp = Vec3f{p.x * p.z / rxy, p.y * p.z / rxy, -rxy} * (kInvPi / (r * r));
                    dtdp = Vec3f{-p.y, p.x, 0.0f} * (kInv2Pi / x2y2);
                }
                break;
            }
            case TextureMappingKind::Cylindrical:
                c.st = {(kPi + std::atan2(p.y, p.x)) * kInv2Pi, p.z};
                if (x2y2 > 0.0f) dsdp = Vec3f{-p.y, p.x, 0.0f} * (kInv2Pi / x2y2);
                dtdp = {0.0f, 0.0f, 1.0f};
                break;
            case TextureMappingKind::Planar:
            case TextureMappingKind::Uv:
                c.st = {dot(p, v1), dot(p, v2)};
                dsdp = v1;
                dtdp = v2;
                break;
        }
        c.dsdx = dot(dsdp, dpdx);
        c.dsdy = dot(dsdp, dpdy);
        c.dtdx = dot(dtdp, dpdx);
        c.dtdy = dot(dtdp, dpdy);
        return c;
    }
};

}  // namespace penumbra
