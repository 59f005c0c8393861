// Random points and directions for tests that draw scenes or queries from a seeded engine.
#pragma once

#include <random>

#include "core/sampling.h"
#include "core/vec.h"

namespace penumbra::testing {

// A point uniform in the cube [-extent, extent]^3.
inline Vec3f randomPoint(std::mt19937& rng, float extent) {
    std::uniform_real_distribution<float> u(-extent, extent);
    return {u(rng), u(rng), u(rng)};
}

// A direction uniform on the unit sphere.
inline Vec3f randomUnit(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    return sampleUniformSphere({u(rng), u(rng)});
}

}  // namespace penumbra::testing
