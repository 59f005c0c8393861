// Lambertian (ideal diffuse) reflection, f = albedo / pi, sampled with a cosine-weighted
// hemisphere so that the sample weight is exactly the albedo.
#pragma once

#include <optional>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"

namespace penumbra {

struct Lambert {
    Rgb albedo{0.5f, 0.5f, 0.5f};

    struct Sample {
        Vec3f wi;
        Rgb weight;
        float pdf;
    };

    static bool sameHemisphere(Vec3f a, Vec3f b) { return a.z * b.z > 0.0f; }

    Rgb eval(Vec3f wo, Vec3f wi) const { return sameHemisphere(wo, wi) ? albedo * kInvPi : Rgb(0.0f); }
    float pdf(Vec3f wo, Vec3f wi) const { return sameHemisphere(wo, wi) ? cosineHemispherePdf(std::abs(wi.z)) : 0.0f; }
    std::optional<Sample> sample(Vec3f wo, Vec2f u) const {
        if (wo.z == 0.0f) return std::nullopt;
        Vec3f wi = sampleCosineHemisphere(u);
        if (wo.z < 0.0f) wi.z = -wi.z;
        const float pdfValue = cosineHemispherePdf(std::abs(wi.z));
        if (!(pdfValue > 0.0f)) return std::nullopt;
        return Sample{wi, albedo, pdfValue};
    }
};

}  // namespace penumbra
