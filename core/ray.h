// A ray with its valid parameter interval and the time at which it travels.
#pragma once

#include <limits>

#include "core/vec.h"

namespace penumbra {

struct Ray {
    Vec3f origin;
    Vec3f direction;  // not necessarily normalized
    float tnear = 0.0f;
    float tfar = std::numeric_limits<float>::infinity();
    float time = 0.0f;  // shutter fraction in [0, 1]: 0 when the shutter opens, 1 when it closes

    Vec3f at(float t) const { return origin + direction * t; }
};

}  // namespace penumbra
