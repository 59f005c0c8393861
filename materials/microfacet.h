// The microfacet distributions shared by the rough materials, with Smith's height-correlated
// masking-shadowing G (Heitz 2014, "Understanding the masking-shadowing function in
// microfacet-based BRDFs"):
//   - GGX (Trowbridge-Reitz), the default: long tails, the look of most measured surfaces;
//     sampled from the normals visible from wo (Heitz 2018, "Sampling the GGX distribution of
//     visible normals"), whose density D_w(wm) = G1(w) |w.wm| D(wm) / |w.z| leaves only G / G1 in
//     the weight;
//   - Beckmann (a Gaussian distribution of slopes): short tails, the classic of Cook-Torrance and
//     of many reference scenes; sampled from D(wm) cos(theta_m), its slopes being normal with
//     standard deviation alpha / sqrt(2) (Walter et al. 2007, eq. 28).
//
// Roughness. alpha_x and alpha_y are the slopes' scales along the local x and y axes (isotropic
// when equal). Scene files give either `roughness` r in [0, 1] with alpha = r^2 (the perceptual
// parameter of Disney, Cycles and Blender) or `alpha` directly (pbrt-v4's roughness with
// `remaproughness false`, Mitsuba's and Tungsten's alpha); see roughnessToAlpha. Below
// kSmoothAlpha a surface is smooth: the scene loader gives it the smooth material instead (a
// float lobe that narrow is all rounding).
//
// Directions are in the local frame (normal = +z); normals wm are on the +z side.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/sampling.h"
#include "core/vec.h"

namespace penumbra {

// Narrower than this a lobe counts as a delta (pbrt-v4's EffectivelySmooth uses the same bound).
inline constexpr float kSmoothAlpha = 1e-3f;

// alpha = roughness^2: a roughness ramp in equal steps looks evenly spaced.
inline float roughnessToAlpha(float roughness) { return roughness * roughness; }

enum class MicrofacetKind : uint8_t { Ggx, Beckmann };

struct MicrofacetDistribution {
    float alphaX = 0.1f, alphaY = 0.1f;
    MicrofacetKind kind = MicrofacetKind::Ggx;

    // D(wm): microfacet normals per unit solid angle and unit macro area, for wm.z > 0. With the
    // slopes scaled to unit roughness, s2 = (x / ax)^2 + (y / ay)^2 over z^2 = tan^2 theta_m:
    //   GGX:      1 / (pi ax ay z^4 (1 + s2)^2)
    //   Beckmann: exp(-s2) / (pi ax ay z^4)
    float D(Vec3f wm) const {
        if (!(wm.z > 0.0f)) return 0.0f;
        const float x = wm.x / alphaX, y = wm.y / alphaY, z2 = wm.z * wm.z;
        if (kind == MicrofacetKind::Ggx) {
            const float s = x * x + y * y + z2;  // z^2 (1 + s2), free of a division by z
            return 1.0f / (kPi * alphaX * alphaY * s * s);
        }
        return std::exp(-(x * x + y * y) / z2) / (kPi * alphaX * alphaY * z2 * z2);
    }

    // Smith's Lambda(w), with a = 1 / (alpha tan theta) for the projected roughness alpha in w's
    // azimuth: GGX (sqrt(1 + 1 / a^2) - 1) / 2; Beckmann (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)).
    float lambda(Vec3f w) const {
        const float z2 = w.z * w.z;
        if (z2 == 0.0f) return INFINITY;
        const float ax = alphaX * w.x, ay = alphaY * w.y;
        const float alpha2Tan2 = (ax * ax + ay * ay) / z2;  // 1 / a^2
        if (kind == MicrofacetKind::Ggx) return 0.5f * (std::sqrt(1.0f + alpha2Tan2) - 1.0f);
        if (alpha2Tan2 == 0.0f) return 0.0f;
        const float a = 1.0f / std::sqrt(alpha2Tan2);
        return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * std::sqrt(kPi));
    }
    // The fraction of the microsurface visible from w.
    float G1(Vec3f w) const { return 1.0f / (1.0f + lambda(w)); }
    // The fraction visible from both directions, height-correlated (they are masked together).
    float G(Vec3f wo, Vec3f wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }

    // A microfacet normal for light arriving along w (w.z > 0), drawn with density normalPdf.
    Vec3f sampleNormal(Vec3f w, Vec2f u) const {
        return kind == MicrofacetKind::Ggx ? sampleVisibleGgxNormal(w, u) : sampleBeckmannNormal(u);
    }
    // The density of sampleNormal(w, .) per unit solid angle of wm: the visible normals' for GGX,
    // D(wm) cos(theta_m) for Beckmann.
    float normalPdf(Vec3f w, Vec3f wm) const {
        if (kind == MicrofacetKind::Beckmann) return D(wm) * wm.z;
        const float cosine = dot(w, wm);
        if (!(w.z > 0.0f) || !(cosine > 0.0f)) return 0.0f;
        return G1(w) * cosine * D(wm) / w.z;
    }

    // The density of wi = reflectAbout(wo, wm) when wm is drawn by sampleNormal(wo): the normals'
    // density times the Jacobian dwm / dwi = 1 / (4 wo.wm) of reflection.
    float reflectionPdf(Vec3f wo, Vec3f wm) const {
        const float cosine = dot(wo, wm);
        return cosine > 0.0f ? normalPdf(wo, wm) / (4.0f * cosine) : 0.0f;
    }
    // D G / (4 wo.z wi.z): a reflection lobe without its Fresnel factor, for wo, wi, wm on +z.
    float reflectionWithoutFresnel(Vec3f wo, Vec3f wi, Vec3f wm) const {
        return D(wm) * G(wo, wi) / (4.0f * wo.z * wi.z);
    }

private:
    // Stretch w to the configuration with unit roughness, sample the projected area of a
    // hemisphere there (a disk, warped toward the visible half), and unstretch the normal.
    Vec3f sampleVisibleGgxNormal(Vec3f w, Vec2f u) const {
        const Vec3f wh = normalize(Vec3f{alphaX * w.x, alphaY * w.y, w.z});
        // An orthonormal basis (t1, t2, wh) around the stretched direction.
        const float lengthXY2 = wh.x * wh.x + wh.y * wh.y;
        const Vec3f t1 =
            lengthXY2 > 0.0f ? Vec3f{-wh.y, wh.x, 0.0f} / std::sqrt(lengthXY2) : Vec3f{1.0f, 0.0f, 0.0f};
        const Vec3f t2 = cross(wh, t1);
        // A uniform point on the unit disk; its t2 coordinate is moved into the visible part,
        // which is a half disk scaled by (1 + wh.z) / 2 in t2, above the ellipse's projection.
        const float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
        const float p1 = r * std::cos(phi);
        float p2 = r * std::sin(phi);
        const float s = 0.5f * (1.0f + wh.z);
        p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
        const Vec3f nh = t1 * p1 + t2 * p2 + wh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
        return normalize(Vec3f{alphaX * nh.x, alphaY * nh.y, std::max(1e-6f, nh.z)});
    }
    // The slopes (-x / z, -y / z) of a Beckmann surface are normal with standard deviations
    // alpha_x / sqrt(2) and alpha_y / sqrt(2) (Box-Muller), and D(wm) cos(theta_m) d wm is their
    // density.
    Vec3f sampleBeckmannNormal(Vec2f u) const {
        const float r = std::sqrt(-std::log1p(-u.x)), phi = 2.0f * kPi * u.y;
        return normalize(Vec3f{-alphaX * r * std::cos(phi), -alphaY * r * std::sin(phi), 1.0f});
    }
};

// A reflected pair of directions turned to the +z side, and the microfacet normal between them.
struct ReflectionPair {
    Vec3f wo, wi, wm;
};
// Nothing when wo and wi lie on different sides (or one on the surface) or are opposite.
inline std::optional<ReflectionPair> reflectionPair(Vec3f wo, Vec3f wi) {
    if (!(wo.z * wi.z > 0.0f)) return std::nullopt;
    const float side = wo.z > 0.0f ? 1.0f : -1.0f;
    wo.z *= side;
    wi.z *= side;
    const Vec3f sum = wo + wi;
    if (lengthSquared(sum) == 0.0f) return std::nullopt;
    return ReflectionPair{wo, wi, normalize(sum)};
}

}  // namespace penumbra
