// What `penumbra render` tells its user on the terminal: what it is rendering (before the first
// pass), the progress line with its ETA, and the summary of what this run rendered.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "film/film.h"

namespace penumbra {

struct RenderDescription {
    std::string scene;  // the scene file as given
    int width = 0, height = 0;
    std::optional<PixelWindow> crop;
    uint32_t firstSample = 0, endSample = 0;  // the samples this run renders
    std::optional<uint32_t> filmFirstSample;  // when resuming: the first sample the film holds
    std::string resumedFrom;                  // when resuming: the film continued
    std::string sampler;
    uint64_t seed = 0;
    int threads = 0;
    std::string accelerator;
    std::string film;  // "full" / "beauty"
};

// "rendering SCENE: WxH, samples FIRST:END (N spp), SAMPLER sampler, seed S, T threads, BACKEND",
// with the crop window and the resumed film when there are.
std::string describeRender(const RenderDescription& d);

// The summary's first line: "rendered WxH, samples FIRST:END ..." with this run's samples (and the
// film's whole range after a resume).
std::string describeRendered(const RenderDescription& d, uint32_t endReached, double renderSeconds,
                             double buildSeconds);

// A word for a POSIX shell: as it is when it needs no quoting, else in single quotes.
std::string shellWord(const std::string& word);

// A one-line progress bar on stderr with the elapsed time and an ETA, at most ten times a second.
// The ETA is the rate since the first completed tile applied to the tiles left, shown once 2% of
// the tiles and a second have passed: before that, the rate is dominated by the first tiles
// (start-up, caches, the cheap or costly corner of the image the first tiles happen to cover).
class ProgressLine {
public:
    explicit ProgressLine(bool enabled) : enabled_(enabled), start_(Clock::now()) {}
    void update(size_t done, size_t total);

private:
    using Clock = std::chrono::steady_clock;
    bool enabled_;
    Clock::time_point start_;  // elapsed time counts from here (before the scene build)
    std::optional<Clock::time_point> firstTile_;
    size_t firstDone_ = 0;
    Clock::time_point lastPrint_{};
};

}  // namespace penumbra
