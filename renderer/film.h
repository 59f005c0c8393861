// The film keeps per-pixel sums, never averages: weighted radiance, weights, squared radiance
// (for the variance of the mean) and the sample count. Averages are made at output. Sums make
// resume, sample ladders and merges of partial renders exact.
//
// Samples are placed by filter importance sampling (each sample's offset is drawn from the
// reconstruction filter, weight 1), so a sample only ever touches its own pixel: tiles never
// write to each other's pixels and the result does not depend on thread scheduling.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/rgb.h"

namespace penumbra {

struct PixelSums {
    double radiance[3] = {0, 0, 0};         // sum of weight * L
    double radianceSquared[3] = {0, 0, 0};  // sum of weight * L^2
    double weight = 0;                      // sum of weights
    uint32_t sampleCount = 0;

    void add(Rgb value, float sampleWeight) {
        for (int c = 0; c < 3; ++c) {
            radiance[c] += double(sampleWeight) * value[c];
            radianceSquared[c] += double(sampleWeight) * double(value[c]) * value[c];
        }
        weight += sampleWeight;
        ++sampleCount;
    }
    Rgb mean() const {
        if (weight <= 0) return Rgb(0.0f);
        return {float(radiance[0] / weight), float(radiance[1] / weight), float(radiance[2] / weight)};
    }
    // Sample variance of the mean estimate, per channel (0 with fewer than two samples).
    Rgb varianceOfMean() const;
};

class Film {
public:
    Film(int width, int height) : width_(width), height_(height), pixels_(size_t(width) * height) {}

    int width() const { return width_; }
    int height() const { return height_; }
    PixelSums& at(int x, int y) { return pixels_[size_t(y) * width_ + x]; }
    const PixelSums& at(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }

    // Mean radiance, row-major RGB triples, top row first.
    std::vector<float> meanRgb() const;
    uint64_t totalSamples() const;

private:
    int width_, height_;
    std::vector<PixelSums> pixels_;
};

}  // namespace penumbra
