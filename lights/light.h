// The lights a scene names besides its emitting shapes (geometry/emission.h) and its background:
// delta lights, which next-event estimation reaches but rays never hit.
#pragma once

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

struct PointLight {
    Vec3f position;
    Rgb intensity;  // radiant intensity, W/sr per channel
};

// Light from a very distant source arriving along one direction (the sun): hard shadows.
struct DirectionalLight {
    Vec3f direction;  // unit, the direction the light travels
    Rgb irradiance;   // W/m^2 per channel on a surface facing the light
};

}  // namespace penumbra
