// What sampling a light from a reference point gives next-event estimation.
#pragma once

#include <cmath>

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

struct LightSample {
    Vec3f direction;    // unit, from the reference point towards the light
    float distance;     // to the sampled point; infinity for the environment and directional lights
    Vec3f point;        // sampled point on the light (area lights; the position of point lights)
    Vec3f pointError;   // bound on each coordinate's absolute error of point (core/ray_offset.h)
    Vec3f lightNormal;  // front normal at the sampled point (area lights)
    Rgb radiance;       // arriving along -direction (intensity / distance^2 for point lights)
    // Solid-angle density; for delta lights 1 from the light itself. LightSet::sample multiplies
    // in the probability of the light's choice.
    float pdf;
    bool isDelta;
};

// The part of an area light's sample that its shapes share, once ls.point and ls.lightNormal are
// set: the direction and distance from `reference`, and the squared distance and the cosine at the
// light, which its radiance and density need. False where the point is the reference itself.
struct AreaSampleGeometry {
    float distanceSquared;
    float cosAtLight;  // of the light's front normal with the direction back to the reference
};
[[gnu::always_inline]] inline bool connectAreaSample(Vec3f reference, LightSample& ls,
                                                     AreaSampleGeometry& g) {
    const Vec3f toLight = ls.point - reference;
    g.distanceSquared = lengthSquared(toLight);
    if (!(g.distanceSquared > 0.0f)) return false;
    ls.distance = std::sqrt(g.distanceSquared);
    ls.direction = toLight / ls.distance;
    g.cosAtLight = dot(ls.lightNormal, -ls.direction);
    ls.isDelta = false;
    return true;
}

}  // namespace penumbra
