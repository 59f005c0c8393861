#include "tools/adaptive_options.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace penumbra {

void applyAdaptiveOptions(Scene& scene, const std::optional<double>& threshold,
                          const std::optional<int64_t>& minSpp, const std::optional<std::string>& error) {
    if (error && !threshold && !scene.film.adaptive)
        throw InputError(
            "--adaptive-error: what adaptive sampling's threshold bounds; give --adaptive THRESHOLD too (or "
            "film.adaptive in the scene)");
    const std::optional<AdaptiveError> named = error ? parseAdaptiveError(*error) : std::nullopt;
    if (error && !named)
        throw InputError(fmt::format("--adaptive-error: expected relative or absolute, got '{}'", *error));
    const AdaptiveError kind = named.value_or(scene.film.adaptive.value_or(AdaptiveSettings{}).error);
    if (threshold) {
        const double most = AdaptiveSettings::maxThreshold(kind);
        if (!(*threshold > 0.0 && *threshold <= most))
            throw InputError(
                kind == AdaptiveError::Relative
                    ? fmt::format("--adaptive: expected a relative standard error > 0 and <= {:g} (e.g. "
                                  "0.02), got {:g}",
                                  most, *threshold)
                    : fmt::format("--adaptive: expected the image's RMSE, > 0 and <= {:g} (e.g. 0.01), "
                                  "got {:g}",
                                  most, *threshold));
    }
    if (threshold || error) {
        AdaptiveSettings settings = scene.film.adaptive.value_or(AdaptiveSettings{});
        if (threshold) settings.threshold = float(*threshold);
        settings.error = kind;
        // A scene's relative threshold can be no RMSE: a changed kind takes a threshold with it.
        if (!(settings.threshold <= AdaptiveSettings::maxThreshold(kind)))
            throw InputError(
                fmt::format("--adaptive-error {}: the scene's threshold {:g} is out of its range; give "
                            "--adaptive THRESHOLD too",
                            adaptiveErrorName(kind), settings.threshold));
        scene.film.adaptive = settings;
    }
    if (minSpp) {
        if (!scene.film.adaptive)
            throw InputError(
                "--min-spp: the samples before adaptive sampling's first decision; give --adaptive "
                "THRESHOLD too (or film.adaptive in the scene)");
        if (*minSpp < AdaptiveSettings::kMinMinSamples || *minSpp > (int64_t(1) << 30))
            throw InputError(fmt::format("--min-spp: expected an integer in [{}, {}], got {}",
                                         AdaptiveSettings::kMinMinSamples, int64_t(1) << 30, *minSpp));
        scene.film.adaptive->minSamples = uint32_t(*minSpp);
    }
}

std::string describeAdaptiveRender(const Film& film, const PixelWindow& window,
                                   const AdaptiveSettings& settings, uint32_t endSample) {
    uint64_t samples = 0;
    uint32_t least = UINT32_MAX, most = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x) {
            const uint32_t n = film.at(x, y).sampleCount;
            samples += n;
            least = std::min(least, n);
            most = std::max(most, n);
        }
    const double pixels = double(window.width()) * double(window.height());
    const double mean = pixels > 0 ? double(samples) / pixels : 0.0;
    return fmt::format(
        "adaptive {} ({}min {} spp): {} samples, mean {:.1f} spp, {:.0f}% of {} spp everywhere; per pixel "
        "{} to {} (the spp channel of part \"sums\")",
        settings.threshold, settings.error == AdaptiveError::Absolute ? "image RMSE, " : "",
        settings.minSamples, samples, mean, endSample > 0 ? 100.0 * mean / endSample : 0.0, endSample,
        pixels > 0 ? least : 0, most);
}

}  // namespace penumbra
