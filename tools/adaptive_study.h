// `penumbra converge --adaptive`: adaptive sampling against fixed sample counts at equal error.
//
// Each rung n of the ladder (from --min-spp on) maps to a threshold: the median, over the pixels,
// of the relative standard error (renderer/adaptive_sampling.h) that the fixed render's film has
// at n samples. An adaptive render at that threshold (up to kMaxSppFactor times the top rung per
// pixel) stops the pixels that are already as clean as the median pixel of the fixed render and
// spends the samples on the others, so its error lies near the fixed render's at n: the runs
// sweep the same range of errors as the ladder. Then, for each fixed rung, the time and the
// samples the adaptive runs need to reach the rung's RMSE are interpolated on their log-log curve
// (RMSE against seconds, RMSE against samples), and set against the fixed render's.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra {

struct AdaptiveRun {
    uint32_t rung = 0;  // the fixed rung the threshold was taken from
    float threshold = 0;
    uint32_t maxSpp = 0;
    double mse = 0, rmse = 0;
    double seconds = 0;    // tracing, as the fixed rungs count it
    uint64_t samples = 0;  // samples spent, in all
    double meanSpp = 0;
};

// One fixed rung against the adaptive runs at its error; adaptive values are NaN where the rung's
// RMSE lies outside the errors the adaptive runs reached.
struct EqualErrorPoint {
    uint32_t spp = 0;
    double rmse = 0;
    double fixedSeconds = 0, adaptiveSeconds = 0;
    double fixedSamples = 0, adaptiveSamples = 0;
};

struct AdaptiveStudy {
    uint32_t minSamples = 16;
    AdaptiveError error = AdaptiveError::Relative;
    std::vector<AdaptiveRun> runs;
    std::vector<EqualErrorPoint> equalError;
};

// A rung's threshold: the median relative standard error of the film's pixels (0 when none has an
// estimate).
float medianRelativeError(const Film& film);

// Adaptive renders of `scene` at `thresholds` (from rungs `rungs`, parallel), each measured by
// `measure` (MSE and RMSE against the reference), with the criterion `error`.
struct RungMeasure {
    double mse = 0, rmse = 0;
};
std::vector<AdaptiveRun> runAdaptiveRenders(const Scene& scene, const RenderOptions& base,
                                            const std::vector<uint32_t>& rungs,
                                            const std::vector<float>& thresholds, uint32_t minSamples,
                                            uint32_t maxSpp,
                                            const std::function<RungMeasure(const Film&)>& measure,
                                            const std::function<void(const std::string&)>& log,
                                            AdaptiveError error = AdaptiveError::Relative);

// The equal-error comparison of fixed rungs (spp, RMSE, seconds) with the adaptive runs.
std::vector<EqualErrorPoint> compareAtEqualError(const std::vector<uint32_t>& spp,
                                                 const std::vector<double>& rmse,
                                                 const std::vector<double>& seconds, double pixels,
                                                 const std::vector<AdaptiveRun>& runs);

// Times the top rung per pixel that the adaptive runs may spend.
constexpr uint32_t kAdaptiveMaxSppFactor = 4;

}  // namespace penumbra
