#include "renderer/adaptive_sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// The mean over the channels of the variance of the pixel's mean (both criteria start from it).
double channelMeanVarianceOfMean(const PixelSums& pixel) {
    const Rgb variance = pixel.varianceOfMean();
    return (double(variance.r) + variance.g + variance.b) / 3.0;
}

}  // namespace

double relativeStandardError(const PixelSums& pixel) {
    if (pixel.sampleCount < 2) return 0.0;
    const Rgb mean = pixel.mean();
    const double meanValue = std::max(0.0, (double(mean.r) + mean.g + mean.b) / 3.0);
    return std::sqrt(channelMeanVarianceOfMean(pixel)) / (meanValue + kAdaptiveErrorFloor);
}

double sampleStandardDeviation(const PixelSums& pixel) {
    if (pixel.sampleCount < 2) return 0.0;
    return std::sqrt(std::max(0.0, channelMeanVarianceOfMean(pixel)) * double(pixel.sampleCount));
}

ActivePixels::ActivePixels(const Film& film, const PixelWindow& window, uint32_t samples)
    : window_(window), mask_(size_t(window.width()) * size_t(window.height())) {
    size_t i = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x, ++i) {
            mask_[i] = film.sampleCount(x, y) == samples;
            count_ += mask_[i];
        }
}

namespace {

// Per pixel of the window, row-major, whether it is below the threshold (adaptive_sampling.h).
std::vector<uint8_t> belowThreshold(const Film& film, const PixelWindow& window,
                                    const AdaptiveSettings& settings) {
    const int width = window.width(), height = window.height();
    auto pixel = [&](int x, int row) { return film.at(window.x0 + x, window.y0 + row); };
    // Rows in parallel: each pixel's result depends on the film alone, not on the order.
    std::vector<uint8_t> below(size_t(width) * size_t(height));
    if (settings.error == AdaptiveError::Relative) {
        tbb::parallel_for(0, height, [&](int row) {
            for (int x = 0; x < width; ++x)
                below[size_t(row) * width + x] =
                    relativeStandardError(pixel(x, row)) < double(settings.threshold);
        });
        return below;
    }
    // Absolute: sigma_p / n_p < T^2 / mean(sigma), the mean summed by rows, then in row order.
    std::vector<double> sigmas(below.size()), rowSums(size_t(height), 0.0);
    tbb::parallel_for(0, height, [&](int row) {
        double sum = 0.0;
        for (int x = 0; x < width; ++x) {
            const double sigma = sampleStandardDeviation(pixel(x, row));
            sigmas[size_t(row) * width + x] = sigma;
            sum += sigma;
        }
        rowSums[size_t(row)] = sum;
    });
    double sum = 0.0;
    for (const double rowSum : rowSums) sum += rowSum;
    const double meanSigma = sum / (double(width) * double(height));
    const double limit = double(settings.threshold) * double(settings.threshold) / meanSigma;  // inf when 0
    tbb::parallel_for(0, height, [&](int row) {
        for (int x = 0; x < width; ++x) {
            const size_t i = size_t(row) * width + x;
            const uint32_t n = film.sampleCount(window.x0 + x, window.y0 + row);
            // No estimate below two samples counts as 0, as for the relative criterion.
            const double perSample = n >= 2 ? sigmas[i] / double(n) : 0.0;
            below[i] = perSample < limit;
        }
    });
    return below;
}

}  // namespace

size_t ActivePixels::stopConverged(const Film& film, const AdaptiveSettings& settings) {
    const int width = window_.width(), height = window_.height();
    const std::vector<uint8_t> converged = belowThreshold(film, window_, settings);
    std::vector<uint8_t> stop(mask_.size(), 0);
    tbb::parallel_for(0, height, [&](int row) {
        for (int x = 0; x < width; ++x) {
            const size_t i = size_t(row) * width + x;
            if (!mask_[i]) continue;
            bool neighbourhoodConverged = true;
            for (int ny = std::max(0, row - 1); ny <= std::min(height - 1, row + 1); ++ny)
                for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx)
                    neighbourhoodConverged &= converged[size_t(ny) * width + nx] != 0;
            stop[i] = neighbourhoodConverged;
        }
    });
    size_t stopped = 0;
    for (size_t i = 0; i < mask_.size(); ++i)
        if (stop[i]) {
            mask_[i] = 0;
            ++stopped;
        }
    count_ -= stopped;
    return stopped;
}

}  // namespace penumbra
