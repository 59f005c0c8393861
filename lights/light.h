// The lights a scene names besides its emitting shapes (geometry/emission.h) and its background:
// delta lights, which next-event estimation reaches but rays never hit.
#pragma once

#include <algorithm>
#include <numbers>

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

struct PointLight {
    Vec3f position;
    Rgb intensity;  // radiant intensity, W/sr per channel
};

// A spot light's falloff at cos(theta) from its axis: 1 inside cosFalloffStart, 0 outside
// cosFalloffEnd, a smoothstep in cos(theta) between them (pbrt-v4's SmoothStep).
inline float spotFalloff(float cosTheta, float cosFalloffStart, float cosFalloffEnd) {
    if (cosTheta >= cosFalloffStart) return 1.0f;
    if (cosTheta <= cosFalloffEnd) return 0.0f;
    const float t = std::clamp((cosTheta - cosFalloffEnd) / (cosFalloffStart - cosFalloffEnd), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

// A point light whose light is confined to a cone (pbrt-v4's SpotLight): the intensity along a
// direction at angle theta from the axis is `intensity` times a falloff in cos(theta), 1 inside
// cosFalloffStart, 0 outside cosFalloffEnd and a smoothstep between them.
struct SpotLight {
    Vec3f position;
    Vec3f direction;                                     // unit, the cone's axis, the way the light travels
    Rgb intensity;                                       // radiant intensity on the axis, W/sr per channel
    float cosFalloffStart = 1.0f, cosFalloffEnd = 1.0f;  // cosFalloffEnd <= cosFalloffStart

    float falloff(float cosTheta) const { return spotFalloff(cosTheta, cosFalloffStart, cosFalloffEnd); }
    // The power it emits per unit of intensity: the falloff integrated over the sphere,
    // 2 pi ((1 - cosFalloffStart) + (cosFalloffStart - cosFalloffEnd) / 2) (the smoothstep's
    // integral over its band is half the band).
    double solidAngle() const {
        return 2.0 * std::numbers::pi *
               ((1.0 - double(cosFalloffStart)) + (double(cosFalloffStart) - double(cosFalloffEnd)) / 2.0);
    }
};

// Light from a very distant source arriving along one direction (the sun): hard shadows.
struct DirectionalLight {
    Vec3f direction;  // unit, the direction the light travels
    Rgb irradiance;   // W/m^2 per channel on a surface facing the light
};

}  // namespace penumbra
