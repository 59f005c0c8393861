#include "film/film.h"

#include <fmt/format.h>

#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "core/system_memory.h"

namespace penumbra {

Film::Film(int width, int height) : width_(width), height_(height) {
    const size_t pixels = size_t(std::max(width, 0)) * size_t(std::max(height, 0));
    // Checked against the memory available now, not the machine's total: more than that would
    // end in std::bad_alloc or the OOM killer, after minutes of rendering perhaps.
    requireMemory(double(pixels) * double(sizeof(PixelSums) + kOutputBytesPerPixel),
                  fmt::format("a {}x{} film", width, height));
    pixels_.resize(pixels);
}

Rgb PixelSums::varianceOfMean() const {
    const double w = weight;
    if (sampleCount < 2 || w <= 0) return Rgb(0.0f);
    Rgb result;
    float* out[3] = {&result.r, &result.g, &result.b};
    for (int c = 0; c < 3; ++c) {
        const double mean = radiance[c] / w;
        const double meanOfSquares = radianceSquared[c] / w;
        const double variance = std::max(0.0, meanOfSquares - mean * mean) * sampleCount / (sampleCount - 1);
        *out[c] = float(variance / sampleCount);
    }
    return result;
}

Rgb PixelSums::meanAlbedo() const {
    const double w = weight;
    if (w <= 0) return Rgb(0.0f);
    return {float(albedo[0] / w), float(albedo[1] / w), float(albedo[2] / w)};
}

Vec3f PixelSums::meanNormal() const {
    const double w = weight;
    if (w <= 0) return {0.0f, 0.0f, 0.0f};
    return {float(normal[0] / w), float(normal[1] / w), float(normal[2] / w)};
}

float PixelSums::meanDepth() const {
    const double w = hitWeight;
    if (w <= 0) return std::numeric_limits<float>::infinity();
    return float(depth / w);
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

void Film::merge(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw std::invalid_argument("Film::merge: the films differ in size");
    for (size_t i = 0; i < pixels_.size(); ++i)
        if (!pixels_[i].tryMerge(other.pixels_[i]))
            throw InputError(
                fmt::format("pixel ({}, {}) would hold more than 2^32 - 1 samples or a sum beyond "
                            "128 bits: the films cannot both be intact parts of one render",
                            i % size_t(width_), i / size_t(width_)));
}

bool Film::identicalTo(const Film& other) const {
    if (other.width_ != width_ || other.height_ != height_) return false;
    for (size_t i = 0; i < pixels_.size(); ++i) {
        const PixelSums& a = pixels_[i];
        const PixelSums& b = other.pixels_[i];
        for (int c = 0; c < 3; ++c)
            if (!(a.radiance[c] == b.radiance[c]) || !(a.radianceSquared[c] == b.radianceSquared[c]) ||
                !(a.albedo[c] == b.albedo[c]) || !(a.normal[c] == b.normal[c]))
                return false;
        if (!(a.weight == b.weight) || !(a.depth == b.depth) || !(a.hitWeight == b.hitWeight) ||
            a.sampleCount != b.sampleCount)
            return false;
    }
    return true;
}

}  // namespace penumbra
