// Perfectly smooth reflectors: a tinted mirror and a conductor with the complex Fresnel
// reflectance of its index eta + i k (per RGB channel, relative to the outside medium). Both
// reflect wo about the shading normal and nothing else: a delta distribution, sampled with
// probability 1, whose weight is the reflectance itself.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/dielectric.h"
#include "materials/fresnel.h"

namespace penumbra {

struct Mirror {
    Rgb tint{1.0f, 1.0f, 1.0f};  // reflectance at every angle, each channel in [0, 1]

    static constexpr BsdfFlags kFlags = kSpecularReflection;

    std::optional<BsdfSample> sample(Vec3f wo, float /*uLobe*/, Vec2f /*u*/, bool /*front*/) const {
        if (wo.z == 0.0f) return std::nullopt;
        return BsdfSample{reflectAboutZ(wo), tint, 1.0f, kFlags};
    }
    Rgb eval(Vec3f, Vec3f, bool) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f, bool) const { return 0.0f; }
    Rgb reflectanceForAov() const { return tint; }
};

// pbrt-v4's artist-friendly conductor: with eta 1, the extinction k = 2 sqrt(r) / sqrt(1 - r) (r
// below 0.9999) makes the Fresnel reflectance at normal incidence, k^2 / (4 + k^2), exactly r.
inline Rgb conductorKForReflectance(Rgb r) {
    auto k = [](float rc) {
        const float c = std::clamp(rc, 0.0f, 0.9999f);
        return 2.0f * std::sqrt(c) / std::sqrt(1.0f - c);
    };
    return {k(r.r), k(r.g), k(r.b)};
}

struct Conductor {
    // Gold-like defaults; the loader requires both.
    Rgb eta{0.143f, 0.374f, 1.442f};
    Rgb k{3.983f, 2.385f, 1.603f};
    // A factor on the reflectance, each channel in [0, 1] (Tungsten's albedo, Mitsuba's
    // specular_reflectance): 1 is the physical metal.
    Rgb tint{1.0f, 1.0f, 1.0f};

    Rgb reflectance(Vec3f wo) const { return fresnelComplex(std::abs(wo.z), eta, k) * tint; }

    static constexpr BsdfFlags kFlags = kSpecularReflection;

    std::optional<BsdfSample> sample(Vec3f wo, float /*uLobe*/, Vec2f /*u*/, bool /*front*/) const {
        if (wo.z == 0.0f) return std::nullopt;
        return BsdfSample{reflectAboutZ(wo), reflectance(wo), 1.0f, kFlags};
    }
    Rgb eval(Vec3f, Vec3f, bool) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f, bool) const { return 0.0f; }
    // At normal incidence, as denoisers expect an albedo.
    Rgb reflectanceForAov() const { return reflectance(Vec3f{0.0f, 0.0f, 1.0f}); }
};

}  // namespace penumbra
