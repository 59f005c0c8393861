// The energy-conserving, normalized modified Phong model (Lafortune & Willems, "Using the modified
// Phong reflectance model for physically based rendering", 1994):
//
//     f(wo, wi) = kd / pi + ks (n + 2) / (2 pi) cos^n(alpha),
//
// alpha being the angle between wi and the mirror direction of wo (cos clamped at 0). The factor
// (n + 2) / (2 pi) makes the specular lobe reflect exactly ks at normal incidence; elsewhere the
// horizon clips part of the lobe, so the albedo is at most kd + ks <= 1 (the loader enforces this
// per channel).
//
// The exponent sets the highlight's width. The lobe falls to half its peak at the angle
// alpha_half = acos(2^(-1/n)):
//     n = 1: 60 deg,  n = 10: 21.1 deg,  n = 100: 6.7 deg,  n = 1000: 2.1 deg,  n = 10000: 0.67 deg
// (for large n, alpha_half ~ sqrt(2 ln 2 / n) radians, i.e. ten times the exponent narrows the
// highlight by sqrt(10)). n = 0 spreads the "specular" part uniformly over the hemisphere around
// the mirror direction.
//
// Sampling picks a lobe with probability proportional to its albedo's luminance (kd vs ks), then a
// cosine-weighted direction (diffuse) or a direction around the mirror direction with density
// (n + 1) / (2 pi) cos^n(alpha) (specular). pdf() is the combined density of both strategies, as
// MIS requires. Specular samples that fall below the horizon are rejected (no sample), so the
// density of the directions returned integrates to less than 1 at oblique incidence.
//
// Like Lambert, the model is evaluated on the side where wo lies.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/fresnel.h"

namespace penumbra {

struct Phong {
    Rgb kd{0.5f, 0.5f, 0.5f};
    Rgb ks{0.0f, 0.0f, 0.0f};
    float exponent = 10.0f;

    static constexpr BsdfFlags kFlags = BsdfFlags::Diffuse | BsdfFlags::Glossy | BsdfFlags::Reflection;

    // Probability of sampling the specular lobe.
    float specularProbability() const {
        const float d = kd.luminance(), s = ks.luminance();
        return (d + s) > 0.0f ? s / (d + s) : 0.0f;
    }

    // Density of the specular lobe around the mirror direction, as a function of cos(alpha).
    float lobePdf(float cosAlpha) const {
        return cosAlpha > 0.0f ? (exponent + 1.0f) * (0.5f * kInvPi) * std::pow(cosAlpha, exponent) : 0.0f;
    }

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        if (!(wo.z * wi.z > 0.0f)) return Rgb(0.0f);
        const float cosAlpha = dot(reflectAboutZ(wo), wi);
        Rgb f = kd * kInvPi;
        if (cosAlpha > 0.0f) f += ks * ((exponent + 2.0f) * (0.5f * kInvPi) * std::pow(cosAlpha, exponent));
        return f;
    }

    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        if (!(wo.z * wi.z > 0.0f)) return 0.0f;
        const float pSpecular = specularProbability();
        return (1.0f - pSpecular) * cosineHemispherePdf(std::abs(wi.z)) +
               pSpecular * lobePdf(dot(reflectAboutZ(wo), wi));
    }

    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool /*front*/ = true) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float pSpecular = specularProbability();
        if (kd.isBlack() && ks.isBlack()) return std::nullopt;
        Vec3f wi;
        const bool specularLobe = uLobe < pSpecular;
        if (specularLobe) {
            // cos(alpha) = u^(1 / (n + 1)), computed as 1 - cos = -expm1(ln(u) / (n + 1)) so that
            // sin(alpha) keeps its precision for narrow lobes.
            const float oneMinusCos = -std::expm1(std::log(1.0f - u.x) / (exponent + 1.0f));
            const float cosAlpha = 1.0f - oneMinusCos;
            const float sinAlpha = std::sqrt(std::max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
            const Vec2f azimuth = cosSinTurn(u.y);
            const Vec3f local{sinAlpha * azimuth.x, sinAlpha * azimuth.y, cosAlpha};
            // A frame around the mirror direction r (unit).
            const Vec3f r = reflectAboutZ(wo);
            const float sign = std::copysign(1.0f, r.z);
            const float a = -1.0f / (sign + r.z);
            const float b = r.x * r.y * a;
            const Vec3f s{1.0f + sign * r.x * r.x * a, sign * b, -sign * r.x};
            const Vec3f t{b, sign + r.y * r.y * a, -r.y};
            wi = s * local.x + t * local.y + r * local.z;
            if (!(wi.z * wo.z > 0.0f)) return std::nullopt;  // below the horizon
        } else {
            wi = sampleCosineHemisphere(u);
            if (wo.z < 0.0f) wi.z = -wi.z;
        }
        const float pdfValue = pdf(wo, wi, true);
        if (!(pdfValue > 0.0f)) return std::nullopt;
        return BsdfSample{wi, eval(wo, wi, true) * (std::abs(wi.z) / pdfValue), pdfValue,
                          (specularLobe ? BsdfFlags::Glossy : BsdfFlags::Diffuse) | BsdfFlags::Reflection};
    }
    Rgb reflectanceForAov() const { return kd + ks; }
};

}  // namespace penumbra
