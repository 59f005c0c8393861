// A sphere as the scene gives it. When its `motion` moves, center and radius are in object space
// and motion.at(time) places it in the world (as for TriangleMesh).
#pragma once

#include <cstdint>
#include <string>

#include "core/motion.h"
#include "core/vec.h"
#include "geometry/emission.h"

namespace penumbra {

struct Sphere {
    std::string name;
    Vec3f center;
    float radius = 1.0f;  // > 0; the front side is the outside
    uint32_t material = 0;
    Emission emission;
    MotionTransform motion;
    // Whether hits need the sphere's (u, v): only for a textured material or emission. The loader
    // clears it for the others, which then skip an arctangent and an arccosine per hit.
    bool needsUv = true;
};

}  // namespace penumbra
