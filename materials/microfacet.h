// The GGX (Trowbridge-Reitz) microfacet distribution shared by the rough materials: the normal
// distribution D, Smith's height-correlated masking-shadowing G (Heitz 2014, "Understanding the
// masking-shadowing function in microfacet-based BRDFs"), and sampling of the distribution of
// normals visible from a direction (Heitz 2018, "Sampling the GGX distribution of visible
// normals"), whose density D_w(wm) = G1(w) |w.wm| D(wm) / |w.z| leaves only G / G1 in the weight.
//
// Roughness. alpha_x and alpha_y are the distribution's slopes along the local x and y axes
// (isotropic when equal). Scene files give either `roughness` r in [0, 1] with alpha = r^2 (the
// perceptual parameter of Disney, Cycles and Blender) or `alpha` directly (pbrt-v4's roughness
// with `remaproughness false`); see roughnessToAlpha. Below kSmoothAlpha a surface is smooth: the
// scene loader gives it the smooth material instead (a float GGX lobe that narrow is all rounding).
//
// Directions are in the local frame (normal = +z); the functions take w on either side and
// answer for the microsurface facing w's side unless they say otherwise.
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

struct GgxDistribution {
    float alphaX = 0.1f, alphaY = 0.1f;

    // D(wm): microfacet normals per unit solid angle and unit macro area, for wm.z > 0.
    //   D = 1 / (pi ax ay ((x / ax)^2 + (y / ay)^2 + z^2)^2)
    // (the usual tan^2 form multiplied through by cos^4, which has no division by cos).
    float D(Vec3f wm) const {
        if (!(wm.z > 0.0f)) return 0.0f;
        const float x = wm.x / alphaX, y = wm.y / alphaY;
        const float s = x * x + y * y + wm.z * wm.z;
        return 1.0f / (kPi * alphaX * alphaY * s * s);
    }

    // Smith's Lambda(w) = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2, with alpha^2 tan^2 theta =
    // ((ax x)^2 + (ay y)^2) / z^2 for the projected roughness in w's azimuth.
    float lambda(Vec3f w) const {
        const float z2 = w.z * w.z;
        if (z2 == 0.0f) return INFINITY;
        const float ax = alphaX * w.x, ay = alphaY * w.y;
        const float alpha2Tan2 = (ax * ax + ay * ay) / z2;
        return 0.5f * (std::sqrt(1.0f + alpha2Tan2) - 1.0f);
    }
    // The fraction of the microsurface visible from w.
    float G1(Vec3f w) const { return 1.0f / (1.0f + lambda(w)); }
    // The fraction visible from both directions, height-correlated (they are masked together).
    float G(Vec3f wo, Vec3f wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }

    // Density of the normals visible from w (w.z > 0), per unit solid angle of wm.
    float visibleNormalPdf(Vec3f w, Vec3f wm) const {
        const float cosine = dot(w, wm);
        if (!(w.z > 0.0f) || !(cosine > 0.0f)) return 0.0f;
        return G1(w) * cosine * D(wm) / w.z;
    }

    // A normal drawn from the normals visible from w (w.z > 0) with density visibleNormalPdf:
    // stretch w to the configuration with unit roughness, sample the projected area of a
    // hemisphere there (a disk, warped toward the visible half), and unstretch the normal.
    Vec3f sampleVisibleNormal(Vec3f w, Vec2f u) const {
        const Vec3f wh = normalize(Vec3f{alphaX * w.x, alphaY * w.y, w.z});
        // An orthonormal basis (t1, t2, wh) around the stretched direction.
        const float lengthXY2 = wh.x * wh.x + wh.y * wh.y;
        const Vec3f t1 = lengthXY2 > 0.0f ? Vec3f{-wh.y, wh.x, 0.0f} / std::sqrt(lengthXY2) : Vec3f{1.0f, 0.0f, 0.0f};
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

    // The density of wi = reflectAbout(wo, wm) when wm is drawn by sampleVisibleNormal(wo): the
    // normals' density times the Jacobian dwm / dwi = 1 / (4 wo.wm) of reflection.
    float reflectionPdf(Vec3f wo, Vec3f wm) const {
        const float cosine = dot(wo, wm);
        return cosine > 0.0f ? visibleNormalPdf(wo, wm) / (4.0f * cosine) : 0.0f;
    }
    // D G / (4 wo.z wi.z): a reflection lobe without its Fresnel factor, for wo, wi, wm on +z.
    float reflectionWithoutFresnel(Vec3f wo, Vec3f wi, Vec3f wm) const {
        return D(wm) * G(wo, wi) / (4.0f * wo.z * wi.z);
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
