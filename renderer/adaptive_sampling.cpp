#include "renderer/adaptive_sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace penumbra {

double relativeStandardError(const PixelSums& pixel) {
    if (pixel.sampleCount < 2) return 0.0;
    const Rgb variance = pixel.varianceOfMean(), mean = pixel.mean();
    const double meanVariance = (double(variance.r) + variance.g + variance.b) / 3.0;
    const double meanValue = std::max(0.0, (double(mean.r) + mean.g + mean.b) / 3.0);
    return std::sqrt(meanVariance) / (meanValue + kAdaptiveErrorFloor);
}

ActivePixels::ActivePixels(const Film& film, const PixelWindow& window, uint32_t samples)
    : window_(window), mask_(size_t(window.width()) * size_t(window.height())) {
    size_t i = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x, ++i) {
            mask_[i] = film.at(x, y).sampleCount == samples;
            count_ += mask_[i];
        }
}

size_t ActivePixels::stopConverged(const Film& film, float threshold) {
    const int width = window_.width(), height = window_.height();
    // Rows in parallel: each pixel's result depends on the film alone, not on the order.
    std::vector<uint8_t> converged(mask_.size());
    tbb::parallel_for(0, height, [&](int row) {
        for (int x = 0; x < width; ++x)
            converged[size_t(row) * width + x] =
                relativeStandardError(film.at(window_.x0 + x, window_.y0 + row)) < double(threshold);
    });
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
