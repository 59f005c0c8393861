#include "film/adaptive_film.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace penumbra {

std::string formatAdaptiveAttribute(const AdaptiveSettings& settings) {
    return fmt::format("{}:{}", settings.threshold, settings.minSamples);
}

std::optional<AdaptiveSettings> parseAdaptiveAttribute(const std::string& text) {
    const size_t colon = text.find(':');
    if (colon == std::string::npos) return std::nullopt;
    AdaptiveSettings settings;
    const char* begin = text.data();
    const char* end = text.data() + text.size();
    auto [thresholdEnd, thresholdError] = std::from_chars(begin, begin + colon, settings.threshold);
    if (thresholdError != std::errc() || thresholdEnd != begin + colon) return std::nullopt;
    auto [minEnd, minError] = std::from_chars(begin + colon + 1, end, settings.minSamples);
    if (minError != std::errc() || minEnd != end) return std::nullopt;
    if (!(settings.threshold > 0.0f && settings.threshold <= AdaptiveSettings::kMaxThreshold) ||
        settings.minSamples < AdaptiveSettings::kMinMinSamples)
        return std::nullopt;
    return settings;
}

bool adaptiveCountPossible(const AdaptiveSettings& settings, uint32_t count, uint32_t spanned) {
    return count == spanned || (count < spanned && settings.isDecisionPoint(count));
}

}  // namespace penumbra
