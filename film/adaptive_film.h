// What a film of an adaptive render records and what it must hold: the settings as the EXR's
// penumbra:adaptive attribute stores them ("[absolute:]THRESHOLD:MIN_SPP", docs/exr-layout.md), and the
// check that every pixel's sample count is one an adaptive render with them can leave (a pixel
// stops only at a decision point of core/adaptive_schedule.h, or goes on to the end).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/adaptive_schedule.h"
#include "film/film.h"

namespace penumbra {

// "THRESHOLD:MIN_SPP", the threshold in the shortest decimal that reads back to the same float,
// prefixed "absolute:" for the absolute criterion.
std::string formatAdaptiveAttribute(const AdaptiveSettings& settings);
// The settings, or none when `text` is not what formatAdaptiveAttribute writes of valid settings.
std::optional<AdaptiveSettings> parseAdaptiveAttribute(const std::string& text);

// Whether `count` samples (from the film's first sample) is what a pixel of an adaptive render
// with `settings` can hold once the film holds samples up to `first + spanned`: all of them, or a
// decision point below that (where it stopped).
bool adaptiveCountPossible(const AdaptiveSettings& settings, uint32_t count, uint32_t spanned);

}  // namespace penumbra
