// Light from a very distant source arriving along one direction (the sun): hard shadows.
#pragma once

#include <limits>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"

namespace penumbra {

struct DirectionalLight {
    Vec3f direction;  // unit, the direction the light travels
    Rgb irradiance;   // W/m^2 per channel on a surface facing the light

    static constexpr bool kIsDelta = true, kIsInfinite = true;

    static constexpr bool kPointIndependentOfReference = false;
    // The power crossing a disk the size of the scene (pbrt-v4's DistantLight::Phi).
    double power(double sceneRadius) const {
        return kPi * sceneRadius * sceneRadius * double(irradiance.luminance());
    }
    LightBounds bounds(float /*power*/) const { return {}; }  // infinite: chosen by its power share
    bool sample(Vec3f /*reference*/, Vec2f /*u*/, LightSample& ls) const {
        ls.direction = -direction;
        ls.distance = std::numeric_limits<float>::infinity();
        ls.radiance = irradiance;
        ls.pdf = 1.0f;
        ls.isDelta = true;
        return true;
    }
    float pdf(Vec3f /*reference*/, Vec3f /*point*/) const { return 0.0f; }
};

}  // namespace penumbra
