#include "renderer/film.h"

namespace penumbra {

Rgb PixelSums::varianceOfMean() const {
    if (sampleCount < 2 || weight <= 0) return Rgb(0.0f);
    Rgb result;
    float* out[3] = {&result.r, &result.g, &result.b};
    for (int c = 0; c < 3; ++c) {
        const double mean = radiance[c] / weight;
        const double meanOfSquares = radianceSquared[c] / weight;
        const double variance = std::max(0.0, meanOfSquares - mean * mean) * sampleCount / (sampleCount - 1);
        *out[c] = float(variance / sampleCount);
    }
    return result;
}

std::vector<float> Film::meanRgb() const {
    std::vector<float> rgb(pixels_.size() * 3);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const Rgb m = pixels_[i].mean();
        rgb[3 * i] = m.r;
        rgb[3 * i + 1] = m.g;
        rgb[3 * i + 2] = m.b;
    }
    return rgb;
}

uint64_t Film::totalSamples() const {
    uint64_t total = 0;
    for (const auto& p : pixels_) total += p.sampleCount;
    return total;
}

}  // namespace penumbra
