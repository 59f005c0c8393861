#include "tools/adaptive_options.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace penumbra {

void applyAdaptiveOptions(Scene& scene, const std::optional<double>& threshold,
                          const std::optional<int64_t>& minSpp) {
    if (threshold) {
        if (!(*threshold > 0.0 && *threshold <= AdaptiveSettings::kMaxThreshold))
            throw InputError(
                fmt::format("--adaptive: expected a relative standard error > 0 and <= {:g} (e.g. 0.02), "
                            "got {:g}",
                            AdaptiveSettings::kMaxThreshold, *threshold));
        AdaptiveSettings settings = scene.film.adaptive.value_or(AdaptiveSettings{});
        settings.threshold = float(*threshold);
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
        "adaptive {} (min {} spp): {} samples, mean {:.1f} spp, {:.0f}% of {} spp everywhere; per pixel "
        "{} to {} (the spp channel of part \"sums\")",
        settings.threshold, settings.minSamples, samples, mean,
        endSample > 0 ? 100.0 * mean / endSample : 0.0, endSample, pixels > 0 ? least : 0, most);
}

}  // namespace penumbra
