// A measured BRDF (pbrt-v4's `measured` material, Mitsuba's `measured`): the isotropic or anisotropic
// reflectance of a real material as acquired by Dupuy and Jakob 2018 ("An Adaptive Parameterization
// for Efficient Material Acquisition and Rendering") and published in the RGL material database as
// .bsdf files (read by materials/measured_bsdf_reader.h).
//
// The data are tables over the unit square (core/piecewise_linear_2d.h), with the direction toward
// the viewer (theta_o, phi_o) as parameters:
//   - ndf D and sigma (the projected area, the integral of D(wm) max(0, wo.wm)), over the directions
//     of microfacet normals and of wo mapped to the square by u(theta, phi) = (sqrt(2 theta / pi),
//     (phi + pi) / (2 pi)) (for an isotropic material, phi of wm counts from phi_o);
//   - vndf, the distribution of visible normals in that map, a warp of the square: a point s of the
//     square becomes the normal wm = vndf(s), and wi the reflection of wo about it;
//   - the reflectance at s: f cos(theta_i) 4 sigma(wo) / D(wm) (the weight of sampling wi by the
//     visible normals), in RGB (a spectral file is integrated to RGB once when read);
//   - luminance, a density over s proportional to that weight's luminance.
// So  f(wo, wi) = table(s) D(wm) / (4 sigma(wo) cos theta_i),  s = vndf^-1(wm),  and sampling draws s from
// the luminance density, then wm = vndf(s): its pdf in solid angle is
//     pdf = luminance(s) vndf_density(u(wm)) / (4 (wo.wm) 2 pi^2 u_x sin theta_m),
// the last factor the Jacobian of the map from the square to the sphere and of the reflection.
// A file whose "jacobian" flag is 0 stores f cos(theta_i) itself (Mitsuba reads the flag; pbrt-v4
// assumes 1). Files of a symmetric material may store only half or a quarter of the incident azimuths
// ("reduction" 2 or 4, as Mitsuba reads them): wo is mirrored into the stored range first.
//
// Two-sided, like the other reflectors: evaluated on the side where wo lies.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include "core/piecewise_linear_2d.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "materials/bsdf.h"

namespace penumbra {

struct MeasuredBrdfTables {
    std::string description;
    ParameterGrid incidence;  // phi_o, theta_o (radians)
    BilinearTable ndf, sigma;
    PiecewiseLinear2D vndf, luminance;
    BilinearTable reflectance;  // three channels, linear Rec.709
    bool isotropic = true;
    bool storesJacobian = true;  // the file's "jacobian" flag
    int reduction = 1;           // 1, 2 or 4: the part of the azimuths stored
    Rgb albedoAtNormalIncidence{0.0f};
};

namespace measured {

inline float thetaToU(float theta) {
    return std::sqrt(std::max(theta, 0.0f) * (2.0f / std::numbers::pi_v<float>));
}
inline float phiToU(float phi) {
    return (phi + std::numbers::pi_v<float>)*(0.5f / std::numbers::pi_v<float>);
}
inline float uToTheta(float u) { return u * u * (0.5f * std::numbers::pi_v<float>); }
inline float uToPhi(float u) { return (2.0f * u - 1.0f) * std::numbers::pi_v<float>; }

// The angle from +z, accurate near it (acos loses half the digits there).
inline float elevation(Vec3f w) {
    const float distance = std::sqrt(w.x * w.x + w.y * w.y + (w.z - 1.0f) * (w.z - 1.0f));
    return 2.0f * std::asin(std::min(0.5f * distance, 1.0f));
}

// Mirrors w into the azimuths a file of reduction 2 (y <= 0) or 4 (x <= 0 and y <= 0) stores; its
// own inverse. `reference` decides (the viewer's direction), so that wo and wi move together.
inline Vec3f reduce(Vec3f w, Vec3f reference, int reduction) {
    if (reduction < 2) return w;
    const float sy = reference.y, sx = reduction == 4 ? reference.x : sy;
    return {sx >= 0.0f ? -w.x : w.x, sy >= 0.0f ? -w.y : w.y, w.z};
}

}  // namespace measured

struct MeasuredBsdf {
    std::shared_ptr<const MeasuredBrdfTables> tables;

    static constexpr BsdfFlags kFlags = BsdfFlags::Glossy | BsdfFlags::Reflection;

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        const auto v = view(wo, wi);
        if (!v) return Rgb(0.0f);
        const Rgb f = reflectanceAt(v->s, v->uWm, *v) * (1.0f / v->wi.z);
        return f.isFinite() ? f : Rgb(0.0f);  // a grazing wi of a file's extreme values
    }

    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        const auto v = view(wo, wi);
        if (!v) return 0.0f;
        const float p =
            v->vndfDensity * tables->luminance.pdf(v->s, v->blend) / jacobian(v->wo, v->wm, v->uWm.x);
        return std::isfinite(p) ? p : 0.0f;
    }

    std::optional<BsdfSample> sample(Vec3f woIn, float /*uLobe*/, Vec2f u, bool /*front*/) const {
        if (woIn.z == 0.0f) return std::nullopt;
        const float side = woIn.z > 0.0f ? 1.0f : -1.0f;
        const Vec3f woUp{woIn.x, woIn.y, woIn.z * side};
        const Vec3f wo = measured::reduce(woUp, woUp, tables->reduction);
        Incidence in = incidence(wo);
        const PiecewiseLinear2D::Warped s = tables->luminance.sample(u, in.blend);
        const PiecewiseLinear2D::Warped m = tables->vndf.sample(s.point, in.blend);
        const float thetaM = measured::uToTheta(m.point.x);
        const float phiM = measured::uToPhi(m.point.y) + (tables->isotropic ? in.phi : 0.0f);
        const float sinThetaM = std::sin(thetaM);
        const Vec3f wm{std::cos(phiM) * sinThetaM, std::sin(phiM) * sinThetaM, std::cos(thetaM)};
        const float cosM = dot(wo, wm);
        Vec3f wi = wm * (2.0f * cosM) - wo;
        if (!(wi.z > 0.0f) || !(cosM > 0.0f)) return std::nullopt;
        const float pdfValue = m.pdf * s.pdf / jacobian(wo, wm, m.point.x, sinThetaM);
        if (!(pdfValue > 0.0f) || !std::isfinite(pdfValue)) return std::nullopt;
        in.s = s.point;
        const Rgb weight = reflectanceAt(s.point, m.point, in) * (1.0f / pdfValue);
        if (!weight.isFinite()) return std::nullopt;
        wi = measured::reduce(wi, woUp, tables->reduction);
        wi.z *= side;
        return BsdfSample{wi, weight, pdfValue, kFlags};
    }

    Rgb reflectanceForAov() const { return tables->albedoAtNormalIncidence; }

private:
    struct Incidence {
        ParameterBlend blend;
        float phi = 0.0f;
        Vec2f uWo;
        Vec2f s;  // the point of the sample square
    };
    struct View : Incidence {
        Vec3f wo, wi, wm;
        Vec2f uWm;
        float vndfDensity = 0.0f;
    };

    Incidence incidence(Vec3f wo) const {
        Incidence in;
        const float theta = measured::elevation(wo);
        in.phi = std::atan2(wo.y, wo.x);
        const float parameters[2] = {in.phi, theta};
        in.blend = tables->incidence.blend(parameters);
        in.uWo = {measured::thetaToU(theta), measured::phiToU(in.phi)};
        return in;
    }

    // wo and wi on wo's side, mirrored as the file stores them, and where wm lies in the tables.
    std::optional<View> view(Vec3f wo, Vec3f wi) const {
        if (wo.z < 0.0f) {
            wo = -wo;
            wi = -wi;
        }
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return std::nullopt;
        const Vec3f reference = wo;
        wo = measured::reduce(wo, reference, tables->reduction);
        wi = measured::reduce(wi, reference, tables->reduction);
        const Vec3f half = wo + wi;
        const float length = std::sqrt(dot(half, half));
        if (!(length > 0.0f)) return std::nullopt;
        View v;
        static_cast<Incidence&>(v) = incidence(wo);
        v.wo = wo;
        v.wi = wi;
        v.wm = half * (1.0f / length);
        float u = measured::phiToU(std::atan2(v.wm.y, v.wm.x) - (tables->isotropic ? v.phi : 0.0f));
        u -= std::floor(u);
        v.uWm = {measured::thetaToU(measured::elevation(v.wm)), u};
        const PiecewiseLinear2D::Warped inverse = tables->vndf.invert(v.uWm, v.blend);
        v.s = inverse.point;
        v.vndfDensity = inverse.pdf;
        return v;
    }

    // 4 (wo.wm) times the density of the map from the square to wm: d(omega) = 2 pi^2 u_x sin(theta) du.
    static float jacobian(Vec3f wo, Vec3f wm, float ux, float sinThetaM) {
        return 4.0f * dot(wo, wm) *
               std::max(2.0f * std::numbers::pi_v<float> * std::numbers::pi_v<float> * ux * sinThetaM, 1e-6f);
    }
    static float jacobian(Vec3f wo, Vec3f wm, float ux) {
        return jacobian(wo, wm, ux, std::sqrt(std::max(wm.x * wm.x + wm.y * wm.y, 0.0f)));
    }

    // f cos(theta_i) at the square's point s, whose normal lies at uWm in the tables.
    Rgb reflectanceAt(Vec2f s, Vec2f uWm, const Incidence& in) const {
        const std::array<float, 3> table = tables->reflectance.eval3(s, in.blend);
        Rgb value{std::max(table[0], 0.0f), std::max(table[1], 0.0f), std::max(table[2], 0.0f)};
        if (tables->storesJacobian) {
            const ParameterBlend none;
            const float sigma = tables->sigma.eval(in.uWo, none);
            const float scale = sigma > 0.0f ? tables->ndf.eval(uWm, none) / (4.0f * sigma) : 0.0f;
            value = value * scale;
        }
        return value;
    }
};

}  // namespace penumbra
