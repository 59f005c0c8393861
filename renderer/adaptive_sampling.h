// Adaptive sampling: which pixels keep receiving samples (film.adaptive, `--adaptive`).
//
// Two criteria (AdaptiveError), both from the film's own sums (PixelSums::varianceOfMean, the
// `variance.*` AOV).
//
// Relative (the default): the relative standard error of the pixel's mean: the RMS over the three
// channels of the mean's standard error, divided by the mean over the channels plus an absolute floor,
//
//     error = sqrt((v_R + v_G + v_B) / 3) / ((m_R + m_G + m_B) / 3 + kAdaptiveErrorFloor).
//
// Relative, so that a threshold means the same in a bright sky and on a dim wall (0.02: the
// noise left in the pixel is 2% of its value); the floor keeps near-black pixels, whose relative
// error means nothing, from sampling forever. At 0.05 it makes the criterion about a constant noise level
// after the sRGB transfer function for pixel values from 0.01 to 1, where a scene exposed for
// display lives (the slope of sRGB at 0.01 is ~10x its slope at 0.5, and (0.01 + 0.05) / (0.5 +
// 0.05) ~ 1/9). This is the per-pixel form of Dammertz et al.'s criterion ("A hierarchical
// automatic stopping condition for Monte Carlo global illumination", WSCG 2010), which Cycles
// uses (intern/cycles/kernel/film/adaptive_sampling.h) with the difference between the image and
// the image of every other sample in place of the variance; the film holds the variance exactly,
// so we use it.
//
// Absolute: the image's root-mean-square error, the threshold T in scene-linear units. With a
// pixel's per-sample standard deviation sigma_p (the RMS over the channels) and n_p samples, the
// image's mean squared error is the mean over the pixels of sigma_p^2 / n_p; for a given number of
// samples it is least when n_p is proportional to sigma_p (Neyman's allocation: Lagrange's
// condition sigma_p^2 / n_p^2 = lambda for every pixel), and then it is sqrt(lambda) * mean(sigma).
// So the pixels hold their share of an image RMSE of T when sigma_p / n_p <= T^2 / mean(sigma): a
// pixel stops once its sigma_p / n_p (its standard error over sqrt(n_p): what one more sample
// would still take off its squared error, per sample) is below T^2 / mean(sigma), mean(sigma) over
// the rendered window at that decision. Where the noise is spread unevenly (caustics, bright
// bokeh, the edges of motion blur) this reaches a given RMSE with far fewer samples than the
// relative criterion, which spends on every pixel until its noise is a fraction of its value;
// dark regions, whose noise is small in absolute terms, get little: for display, the relative
// criterion. T is a bound: the floor of min_spp samples, the 3x3 neighbourhoods below and a
// stratified sampler (whose error falls faster than the sigma / sqrt(n) the variance assumes)
// leave the image cleaner than T. The sums of mean(sigma) are taken row by row and then in row
// order, so the decision does not depend on the thread count.
//
// A pixel stops when it and its 8 neighbours (within the rendered window) are all below the
// threshold, as Cycles and Dammertz dilate their converged regions: a pixel whose first samples
// all happened to miss a small bright feature has a variance estimate of 0 and would stop, but
// its neighbours see the feature. Stopping is for good: a stopped pixel never samples again, so
// every pixel holds samples [0, k) for its own k, and the pixels still active at any count are
// exactly those that hold all of that count's samples. Decisions are taken at the counts of
// AdaptiveSettings's schedule (core/adaptive_schedule.h) from the film alone, so they do not
// depend on threads, passes or checkpoints, and a resumed render (which finds the active pixels
// by their sample counts) takes the same decisions as an uninterrupted one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/adaptive_schedule.h"
#include "film/film.h"

namespace penumbra {

// The criterion's absolute floor, in scene-linear radiance (see above).
constexpr double kAdaptiveErrorFloor = 0.05;

// The relative standard error of the pixel's mean (0 below two samples: no estimate).
double relativeStandardError(const PixelSums& pixel);
// The per-sample standard deviation of the pixel's samples, the RMS over the channels (0 below
// two samples: no estimate).
double sampleStandardDeviation(const PixelSums& pixel);

// The pixels of a window that still receive samples.
class ActivePixels {
public:
    // The pixels of `window` that hold `samples` samples, all of them so far: the pixels that had
    // not stopped when the film reached that count.
    ActivePixels(const Film& film, const PixelWindow& window, uint32_t samples);

    bool active(int x, int y) const {
        return mask_[size_t(y - window_.y0) * size_t(window_.width()) + size_t(x - window_.x0)] != 0;
    }
    size_t count() const { return count_; }

    // A decision: stops the active pixels whose 3x3 neighbourhood within the window is below
    // `settings`' threshold by its criterion. Returns how many stopped.
    size_t stopConverged(const Film& film, const AdaptiveSettings& settings);

private:
    PixelWindow window_;
    std::vector<uint8_t> mask_;  // row-major over the window: 1 active, 0 stopped
    size_t count_ = 0;
};

}  // namespace penumbra
