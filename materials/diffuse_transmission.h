// A thin diffuse surface that lets light through (a lampshade, a leaf, paper): Lambertian
// reflection R / pi on wo's side and Lambertian transmission T / pi on the other, as pbrt-v4's
// DiffuseTransmissionBxDF. Energy-conserving when R + T <= 1 (its albedo is R + T whatever the
// direction). Sampled by choosing reflection with probability max(R) / (max(R) + max(T)), as
// pbrt-v4 does, then a cosine-weighted direction on the chosen side: the weight is R or T over that
// probability. A thin surface: the path stays in the medium it was in (no refraction, no
// boundary), and both sides are alike.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "materials/bsdf.h"

namespace penumbra {

struct DiffuseTransmission {
    Rgb reflectance{0.25f, 0.25f, 0.25f};
    Rgb transmittance{0.25f, 0.25f, 0.25f};

    static constexpr BsdfFlags kFlags = BsdfFlags::Diffuse | BsdfFlags::Reflection | BsdfFlags::Transmission;

    // The probability of sampling reflection; 0 and 1 when one of R and T is black.
    float reflectionProbability() const {
        const float pr = reflectance.maxComponent(), pt = transmittance.maxComponent();
        return pr + pt > 0.0f ? pr / (pr + pt) : 0.0f;
    }

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        if (wo.z == 0.0f || wi.z == 0.0f) return Rgb(0.0f);
        return (wo.z * wi.z > 0.0f ? reflectance : transmittance) * kInvPi;
    }
    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        if (wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
        const float pr = reflectionProbability();
        return (wo.z * wi.z > 0.0f ? pr : 1.0f - pr) * cosineHemispherePdf(std::abs(wi.z));
    }
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool /*front*/) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float pr = reflectionProbability();
        const float pt = reflectance.maxComponent() + transmittance.maxComponent() > 0.0f ? 1.0f - pr : 0.0f;
        const bool reflect = uLobe < pr;
        const float lobe = reflect ? pr : pt;
        if (!(lobe > 0.0f)) return std::nullopt;
        Vec3f wi = sampleCosineHemisphere(u);
        // Reflection on wo's side, transmission on the other.
        if ((wo.z < 0.0f) == reflect) wi.z = -wi.z;
        const float pdfValue = lobe * cosineHemispherePdf(std::abs(wi.z));
        if (!(pdfValue > 0.0f)) return std::nullopt;
        const BsdfFlags direction = reflect ? BsdfFlags::Reflection : BsdfFlags::Transmission;
        return BsdfSample{wi, (reflect ? reflectance : transmittance) / lobe, pdfValue,
                          BsdfFlags::Diffuse | direction};
    }
    Rgb reflectanceForAov() const { return reflectance; }
};

}  // namespace penumbra
