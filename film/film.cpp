#include "film/film.h"

#include <fmt/format.h>

#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "core/system_memory.h"

namespace penumbra {

Film::Film(int width, int height) : width_(width), height_(height), highWords_(0, PixelSums::kSumCount) {
    const size_t pixels = size_t(std::max(width, 0)) * size_t(std::max(height, 0));
    // Checked against the memory available now, not the machine's total: more than that would
    // end in std::bad_alloc or the OOM killer, after minutes of rendering perhaps.
    requireMemory(double(pixels) * double(bytesPerPixel() + kOutputBytesPerPixel),
                  fmt::format("a {}x{} film", width, height));
    beauty_.resize(pixels);
    aovs_.resize(pixels);
    highWords_ = HighWords(pixels, PixelSums::kSumCount);
}

__int128 Film::sum(size_t pixel, int sum) const {
    return __int128(highWords_.get(pixel, sum)) * (__int128(1) << 64) + low(pixel, sum);
}

void Film::setSum(size_t pixel, int sum, __int128 value) {
    // The low word is the value's low 64 bits read as signed; the high word what remains.
    const auto lowWord = int64_t(uint64_t(static_cast<unsigned __int128>(value)));
    const auto highWord = int64_t((value >> 64) + (lowWord < 0 ? 1 : 0));
    low(pixel, sum) = lowWord;
    if (highWord != 0 || highWords_.get(pixel, sum) != 0) highWords_.at(pixel, sum) = highWord;
}

void Film::addToSum(size_t pixel, int sum, __int128 value) {
    if (value == __int128(int64_t(value))) return addToLow(pixel, sum, int64_t(value));
    __int128 total;
    const bool overflows = __builtin_add_overflow(this->sum(pixel, sum), value, &total);
    PENUMBRA_CHECK(!overflows, "a sum stays within 128 bits");
    if (!overflows) setSum(pixel, sum, total);
}

PixelSums Film::at(int x, int y) const { return sums(index(x, y)); }

PixelSums Film::sums(size_t i) const {
    PixelSums p;
    for (int s = 0; s < PixelSums::kSumCount; ++s) p.sum(s) = ExactSum::fromRaw(sum(i, s));
    p.sampleCount = beauty_[i].sampleCount;
    return p;
}

void Film::add(int x, int y, Rgb value, float sampleWeight, const FirstHitAovs* aovs) {
    const size_t i = index(x, y);
    PixelSums::forEachAddend(value, sampleWeight, aovs, [&](int s, double addend) {
        ExactSum one;
        one.add(addend);
        addToSum(i, s, one.raw());
    });
    ++beauty_[i].sampleCount;
}

void Film::addUnits(int x, int y, const int64_t (&units)[PixelSums::kSumCount], uint32_t samples) {
    const size_t i = index(x, y);
    for (int s = 0; s < PixelSums::kSumCount; ++s) addToLow(i, s, units[s]);
    beauty_[i].sampleCount += samples;
}

void Film::addAddend(int x, int y, int sum, double addend) {
    ExactSum one;
    one.add(addend);
    addToSum(index(x, y), sum, one.raw());
}

void Film::set(int x, int y, const PixelSums& sums) { set(index(x, y), sums); }

void Film::set(size_t i, const PixelSums& sums) {
    for (int s = 0; s < PixelSums::kSumCount; ++s) setSum(i, s, sums.sum(s).raw());
    beauty_[i].sampleCount = sums.sampleCount;
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
    std::vector<float> rgb(beauty_.size() * 3);
    for (size_t i = 0; i < beauty_.size(); ++i) {
        const Rgb m = sums(i).mean();
        rgb[3 * i] = m.r;
        rgb[3 * i + 1] = m.g;
        rgb[3 * i + 2] = m.b;
    }
    return rgb;
}

uint64_t Film::totalSamples() const {
    uint64_t total = 0;
    for (const BeautyPixel& p : beauty_) total += p.sampleCount;
    return total;
}

void Film::merge(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw std::invalid_argument("Film::merge: the films differ in size");
    for (size_t i = 0; i < beauty_.size(); ++i) {
        PixelSums merged = sums(i);
        if (!merged.tryMerge(other.sums(i)))
            throw InputError(
                fmt::format("pixel ({}, {}) would hold more than 2^32 - 1 samples or a sum beyond "
                            "128 bits: the films cannot both be intact parts of one render",
                            i % size_t(width_), i / size_t(width_)));
        set(i, merged);
    }
}

bool Film::identicalTo(const Film& other) const {
    if (other.width_ != width_ || other.height_ != height_) return false;
    for (size_t i = 0; i < beauty_.size(); ++i)
        if (!(sums(i) == other.sums(i))) return false;
    return true;
}

}  // namespace penumbra
