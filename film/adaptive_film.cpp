#include "film/adaptive_film.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <string_view>

namespace penumbra {

// The relative criterion keeps the form it had before there were two, so that films written
// then read the same.
constexpr std::string_view kAbsolutePrefix = "absolute:";

std::string formatAdaptiveAttribute(const AdaptiveSettings& settings) {
    return fmt::format("{}{}:{}", settings.error == AdaptiveError::Absolute ? kAbsolutePrefix : "",
                       settings.threshold, settings.minSamples);
}

std::optional<AdaptiveSettings> parseAdaptiveAttribute(const std::string& text) {
    AdaptiveSettings settings;
    std::string_view rest = text;
    if (rest.starts_with(kAbsolutePrefix)) {
        settings.error = AdaptiveError::Absolute;
        rest.remove_prefix(kAbsolutePrefix.size());
    }
    const size_t colon = rest.find(':');
    if (colon == std::string_view::npos) return std::nullopt;
    const char* begin = rest.data();
    const char* end = rest.data() + rest.size();
    auto [thresholdEnd, thresholdError] = std::from_chars(begin, begin + colon, settings.threshold);
    if (thresholdError != std::errc() || thresholdEnd != begin + colon) return std::nullopt;
    auto [minEnd, minError] = std::from_chars(begin + colon + 1, end, settings.minSamples);
    if (minError != std::errc() || minEnd != end) return std::nullopt;
    if (!(settings.threshold > 0.0f &&
          settings.threshold <= AdaptiveSettings::maxThreshold(settings.error)) ||
        settings.minSamples < AdaptiveSettings::kMinMinSamples)
        return std::nullopt;
    return settings;
}

bool adaptiveCountPossible(const AdaptiveSettings& settings, uint32_t count, uint32_t spanned) {
    return count == spanned || (count < spanned && settings.isDecisionPoint(count));
}

}  // namespace penumbra
