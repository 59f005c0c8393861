// Lambertian (ideal diffuse) reflection, f = albedo / pi, sampled with a cosine-weighted
// hemisphere so that the sample weight is exactly the albedo.
#pragma once

#include <optional>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "materials/bsdf.h"

namespace penumbra {

struct Lambert {
    Rgb albedo{0.5f, 0.5f, 0.5f};

    static constexpr BsdfFlags kFlags = BsdfFlags::Diffuse | BsdfFlags::Reflection;

    static bool sameHemisphere(Vec3f a, Vec3f b) { return a.z * b.z > 0.0f; }

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        return sameHemisphere(wo, wi) ? albedo * kInvPi : Rgb(0.0f);
    }
    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        return sameHemisphere(wo, wi) ? cosineHemispherePdf(std::abs(wi.z)) : 0.0f;
    }
    std::optional<BsdfSample> sample(Vec3f wo, Vec2f u) const {
        if (wo.z == 0.0f) return std::nullopt;
        Vec3f wi = sampleCosineHemisphere(u);
        if (wo.z < 0.0f) wi.z = -wi.z;
        const float pdfValue = cosineHemispherePdf(std::abs(wi.z));
        if (!(pdfValue > 0.0f)) return std::nullopt;
        return BsdfSample{wi, albedo, pdfValue, kFlags};
    }
    std::optional<BsdfSample> sample(Vec3f wo, float /*uLobe*/, Vec2f u, bool /*front*/) const {
        return sample(wo, u);
    }
    Rgb reflectanceForAov() const { return albedo; }
};

}  // namespace penumbra
