// `--adaptive THRESHOLD [--min-spp N]` on the command line (render, converge): checked and applied
// to the scene's film.adaptive; and the summary of where an adaptive render's samples went.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "film/film.h"
#include "scenes/scene.h"

namespace penumbra {

// Sets scene.film.adaptive from --adaptive and --min-spp (over the scene file's film.adaptive);
// throws InputError for a threshold outside (0, 1], a --min-spp below 2, or --min-spp without
// adaptive sampling.
void applyAdaptiveOptions(Scene& scene, const std::optional<double>& threshold,
                          const std::optional<int64_t>& minSpp);

// "adaptive 0.02 (min 16 spp): 1234567 samples, mean 37.2 spp, 58% of 64 spp everywhere; per pixel 16 to 64"
std::string describeAdaptiveRender(const Film& film, const PixelWindow& window,
                                   const AdaptiveSettings& settings, uint32_t endSample);

}  // namespace penumbra
