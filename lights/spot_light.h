// A spot light: a point light whose light is confined to a cone (pbrt-v4's SpotLight).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "lights/point_light.h"

namespace penumbra {

// A spot light's falloff at cos(theta) from its axis: 1 inside cosFalloffStart, 0 outside
// cosFalloffEnd, a smoothstep in cos(theta) between them (pbrt-v4's SmoothStep).
inline float spotFalloff(float cosTheta, float cosFalloffStart, float cosFalloffEnd) {
    if (cosTheta >= cosFalloffStart) return 1.0f;
    if (cosTheta <= cosFalloffEnd) return 0.0f;
    const float t = std::clamp((cosTheta - cosFalloffEnd) / (cosFalloffStart - cosFalloffEnd), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

// The intensity along a direction at angle theta from the axis is `intensity` times a falloff in
// cos(theta): 1 inside cosFalloffStart, 0 outside cosFalloffEnd and a smoothstep between them.
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

    static constexpr bool kIsDelta = true, kIsInfinite = false;

    static constexpr bool kPointIndependentOfReference = true;
    double power(double /*sceneRadius*/) const { return solidAngle() * double(intensity.luminance()); }
    // The falloff's start bounds the full intensity; beyond it, to the cone's end, the emission angle.
    LightBounds bounds(float power) const {
        LightBounds b;
        b.phi = power;
        b.center = position;
        b.axis = direction;
        b.cosThetaO = cosFalloffStart;
        b.cosThetaE = std::cos(std::acos(std::clamp(cosFalloffEnd, -1.0f, 1.0f)) -
                               std::acos(std::clamp(cosFalloffStart, -1.0f, 1.0f)));
        return b;
    }
    bool sample(Vec3f reference, Vec2f /*u*/, LightSample& ls) const {
        if (!samplePointSource(position, intensity, reference, ls)) return false;
        ls.radiance *= falloff(-dot(ls.direction, direction));
        return true;
    }
    float pdf(Vec3f /*reference*/, Vec3f /*point*/) const { return 0.0f; }
};

}  // namespace penumbra
