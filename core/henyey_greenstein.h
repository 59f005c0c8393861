// The Henyey-Greenstein phase function (Henyey and Greenstein 1941): the angular distribution of
// light scattered in a medium, one parameter g in (-1, 1), the mean cosine of the scattering angle
// (g > 0 scatters forward, g < 0 back, g = 0 evenly). Directions follow the BSDFs' convention:
// `wo` and `wi` both point away from the scattering point, so forward scattering is wi = -wo.
// Sampled exactly by inverting its CDF in cos(theta), so the sample's weight p / pdf is 1.
#pragma once

#include <cmath>

#include "core/check.h"
#include "core/frame.h"
#include "core/sampling.h"
#include "core/vec.h"

namespace penumbra {

// Density over the sphere of a scattering angle with cosine `cosTheta` (between -wo and wi).
inline float henyeyGreenstein(float cosTheta, float g) {
    const float denominator = 1.0f + g * g + 2.0f * g * cosTheta;
    return (1.0f / (4.0f * kPi)) * (1.0f - g * g) / (denominator * std::sqrt(std::max(denominator, 0.0f)));
}

struct PhaseSample {
    Vec3f wi;
    float pdf;  // equals the phase function's value: the sample's weight is 1
};

struct HenyeyGreenstein {
    float g = 0.0f;

    // The phase function's value for the pair (per steradian; it integrates to 1 over wi).
    float p(Vec3f wo, Vec3f wi) const { return henyeyGreenstein(dot(wo, wi), g); }
    float pdf(Vec3f wo, Vec3f wi) const { return p(wo, wi); }

    PhaseSample sample(Vec3f wo, Vec2f u) const {
        PENUMBRA_CHECK(std::abs(length(wo) - 1.0f) < 1e-3f, "a phase function's wo has unit length");
        // cos(theta) between wo and wi; near g = 0 the inverse below loses all precision, and
        // the distribution is uniform there anyway.
        float cosTheta;
        if (std::abs(g) < 1e-3f) {
            cosTheta = 1.0f - 2.0f * u.x;
        } else {
            const float s = (1.0f - g * g) / (1.0f + g - 2.0f * g * u.x);
            cosTheta = -(1.0f + g * g - s * s) / (2.0f * g);
        }
        cosTheta = std::clamp(cosTheta, -1.0f, 1.0f);
        const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
        const float phi = 2.0f * kPi * u.y;
        const Frame frame = Frame::fromNormal(wo);
        const Vec3f wi = frame.toWorld({sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta});
        return {wi, henyeyGreenstein(cosTheta, g)};
    }
};

}  // namespace penumbra
