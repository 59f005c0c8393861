// `--adaptive THRESHOLD [--min-spp N] [--adaptive-error relative|absolute]` on the command line
// (render): checked and applied to the scene's film.adaptive; and the summary of where an
// adaptive render's samples went.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "film/film.h"
#include "scenes/scene.h"

namespace penumbra {

// Sets scene.film.adaptive from --adaptive, --min-spp and --adaptive-error (over the scene file's
// film.adaptive); throws InputError for a threshold outside its kind's range ((0, 1] relative),
// a --min-spp below 2, an unknown error kind, or --min-spp or --adaptive-error without adaptive
// sampling.
void applyAdaptiveOptions(Scene& scene, const std::optional<double>& threshold,
                          const std::optional<int64_t>& minSpp,
                          const std::optional<std::string>& error = std::nullopt);

// "adaptive 0.02 (min 16 spp): 1234567 samples, mean 37.2 spp, 58% of 64 spp everywhere; per pixel 16 to 64"
// ("adaptive 0.01 (image RMSE, min 16 spp): ..." for the absolute criterion)
std::string describeAdaptiveRender(const Film& film, const PixelWindow& window,
                                   const AdaptiveSettings& settings, uint32_t endSample);

}  // namespace penumbra
