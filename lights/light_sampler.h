// How next-event estimation chooses among a scene's lights (pbrt-v4's Integrator "lightsampler"):
// by what each can contribute at the vertex (`Bvh`: LightSet::choose, lights/light_tree.h), or by
// power alone everywhere (`Power`, pbrt-v4's PowerLightSampler: the baseline for comparisons).
#pragma once

#include <cstdint>
#include <string_view>

namespace penumbra {

enum class LightSampler : uint8_t { Bvh, Power };

constexpr std::string_view lightSamplerName(LightSampler sampler) {
    return sampler == LightSampler::Bvh ? "bvh" : "power";
}

}  // namespace penumbra
