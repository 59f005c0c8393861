// A point light: all its light leaves one point, with the same intensity in every direction.
#pragma once

#include <cmath>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"

namespace penumbra {

// Light from `position` with radiant intensity `intensity` towards `reference`, written into `ls`
// (the point, spot and goniometric lights' common part): false when the two coincide.
[[gnu::always_inline]] inline bool samplePointSource(Vec3f position, Rgb intensity, Vec3f reference,
                                                     LightSample& ls) {
    const Vec3f toLight = position - reference;
    const float distanceSquared = lengthSquared(toLight);
    if (!(distanceSquared > 0.0f)) return false;
    ls.distance = std::sqrt(distanceSquared);
    ls.direction = toLight / ls.distance;
    ls.point = position;
    ls.radiance = intensity / distanceSquared;
    ls.pdf = 1.0f;
    ls.isDelta = true;
    return true;
}

struct PointLight {
    Vec3f position;
    Rgb intensity;  // radiant intensity, W/sr per channel

    static constexpr bool kIsDelta = true, kIsInfinite = false;

    static constexpr bool kPointIndependentOfReference = true;
    double power(double /*sceneRadius*/) const { return 4.0 * kPi * double(intensity.luminance()); }
    LightBounds bounds(float power) const {
        LightBounds b;
        b.phi = power;
        b.center = position;
        return b;
    }
    bool sample(Vec3f reference, Vec2f /*u*/, LightSample& ls) const {
        return samplePointSource(position, intensity, reference, ls);
    }
    float pdf(Vec3f /*reference*/, Vec3f /*point*/) const { return 0.0f; }  // never sampled by area
};

}  // namespace penumbra
