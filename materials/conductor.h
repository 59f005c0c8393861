// Perfectly smooth reflectors: a tinted mirror and a conductor with the complex Fresnel
// reflectance of its index eta + i k (per RGB channel, relative to the outside medium). Both
// reflect wo about the shading normal and nothing else: a delta distribution, sampled with
// probability 1, whose weight is the reflectance itself.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/dielectric.h"
#include "materials/fresnel.h"

namespace penumbra {

struct Mirror {
    Rgb tint{1.0f, 1.0f, 1.0f};  // reflectance at every angle, each channel in [0, 1]

    std::optional<SpecularSample> sample(Vec3f wo) const {
        if (wo.z == 0.0f) return std::nullopt;
        return SpecularSample{reflectAboutZ(wo), tint, 1.0f, false, 1.0f};
    }
};

struct Conductor {
    // Gold-like defaults; the loader requires both.
    Rgb eta{0.143f, 0.374f, 1.442f};
    Rgb k{3.983f, 2.385f, 1.603f};

    Rgb reflectance(Vec3f wo) const { return fresnelComplex(std::abs(wo.z), eta, k); }

    std::optional<SpecularSample> sample(Vec3f wo) const {
        if (wo.z == 0.0f) return std::nullopt;
        return SpecularSample{reflectAboutZ(wo), reflectance(wo), 1.0f, false, 1.0f};
    }
};

}  // namespace penumbra
