// Adaptive sampling's settings and its schedule: the sample counts at which the renderer decides
// which pixels stop (renderer/adaptive_sampling.h decides how, from the film). The schedule
// depends on the settings alone, never on the pass size, threads or checkpoints, so that every
// way of running a render takes the same decisions at the same counts, and a film's per-pixel
// sample counts can be checked against it (a pixel stops only at a decision point).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <optional>
#include <string_view>

namespace penumbra {

// What adaptive sampling's threshold bounds (renderer/adaptive_sampling.h says how each decides):
//  - Relative: each pixel's relative standard error, the noise left in it as a fraction of its
//    value (0.02: 2%), about the same visible noise everywhere in a displayed image;
//  - Absolute: the image's root-mean-square error in scene-linear units (0.01: an RMSE of 0.01
//    against the converged image), each pixel sampled in proportion to its noise, which is the
//    allocation of a sample budget with the least squared error (what convergence studies measure).
enum class AdaptiveError : uint8_t { Relative, Absolute };

constexpr std::string_view adaptiveErrorName(AdaptiveError error) {
    return error == AdaptiveError::Absolute ? "absolute" : "relative";
}
// The criterion adaptiveErrorName names, or none for another name.
constexpr std::optional<AdaptiveError> parseAdaptiveError(std::string_view name) {
    if (name == "relative") return AdaptiveError::Relative;
    if (name == "absolute") return AdaptiveError::Absolute;
    return std::nullopt;
}

struct AdaptiveSettings {
    // A pixel stops once its error (of kind `error`, renderer/adaptive_sampling.h) and its
    // neighbours' are below this.
    float threshold = 0.0f;
    // Samples every pixel gets before the first decision.
    uint32_t minSamples = 16;
    AdaptiveError error = AdaptiveError::Relative;

    bool operator==(const AdaptiveSettings&) const = default;

    // A relative error above 1 is noise as large as the pixel itself; an absolute one is in the
    // scene's units and bounded only so that its square stays finite. Below two samples there is
    // no variance to estimate.
    static constexpr float kMaxThreshold = 1.0f;
    static constexpr float kMaxAbsoluteThreshold = 1e18f;
    static constexpr float maxThreshold(AdaptiveError error) {
        return error == AdaptiveError::Absolute ? kMaxAbsoluteThreshold : kMaxThreshold;
    }
    static constexpr uint32_t kMinMinSamples = 2;

    // Decisions are taken at minSamples, then at the multiples of a step that grows with the
    // count: 8 below 128 samples, an eighth of the power of two at or below the count above (16
    // from 128, 32 from 256, ...). A pixel so gets at most an eighth more samples than it needed,
    // and a render of N samples takes O(log N) decisions. Steps are multiples of 8, the camera-ray
    // packet size, so that the passes between decisions keep the packets whole.
    static constexpr uint32_t kMinStep = 8;
    static uint32_t stepAt(uint32_t count) {
        return std::max(kMinStep, std::bit_floor(std::max(count, 1u)) / 8);
    }

    // The first decision point after `count` samples.
    uint32_t nextDecisionAfter(uint32_t count) const {
        if (count < minSamples) return minSamples;
        const uint64_t step = stepAt(count);
        return uint32_t(std::min<uint64_t>((count / step + 1) * step, UINT32_MAX));
    }
    bool isDecisionPoint(uint32_t count) const {
        return count == minSamples || (count > minSamples && count % stepAt(count) == 0);
    }
};

}  // namespace penumbra
