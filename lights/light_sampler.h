// How next-event estimation chooses among a scene's lights (pbrt-v4's Integrator "lightsampler"):
// by what each can contribute at the vertex (`Bvh`: LightSet::choose, lights/light_tree.h), or by
// power alone everywhere (`Power`, pbrt-v4's PowerLightSampler: the baseline for comparisons).
#pragma once

#include <cstdint>

namespace penumbra {

enum class LightSampler : uint8_t { Bvh, Power };

}  // namespace penumbra
