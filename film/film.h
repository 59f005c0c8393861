// The film keeps per-pixel sums, never averages: weighted radiance, weights, squared radiance
// (for the variance of the mean), the sample count, and the sums of the first-hit AOVs (albedo,
// shading normal, depth). Averages are made at output. Sums make resume, sample ladders and
// merges of partial renders exact.
//
// Exact sums. Every sum is an ExactSum: a 128-bit integer count of 2^-48 units. Each added value
// is first rounded (towards zero) to a multiple of 2^-48, a function of that value alone, and
// integer addition is associative, so a sum does not depend on the order or grouping of its
// additions: rendering samples [0, 64) and [64, 256) separately and adding the films gives the
// same bits as rendering [0, 256) at once, and so does resuming, checkpointing, or any split of
// the pixels. (Sums of doubles would differ in the last bits: (a + b) + c != a + (b + c).)
// The rounding error, at most 2^-48 ~ 3.6e-15 per sample, is far below float precision. A single
// added value is clamped to +-2^46 (~7e13; radiance squared, for radiance above ~8e6) so that
// 2^32 samples cannot overflow a sum.
//
// Samples are placed by filter importance sampling (each sample's offset is drawn from the
// reconstruction filter, weight 1), so a sample only ever touches its own pixel: tiles never
// write to each other's pixels and the result does not depend on thread scheduling.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/check.h"
#include "core/huge_page_allocator.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "film/aov.h"
#include "film/high_words.h"

namespace penumbra {

// A window of pixels [x0, x1) x [y0, y1).
struct PixelWindow {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    bool intersects(const PixelWindow& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
    bool operator==(const PixelWindow&) const = default;
};

// A sum of doubles kept exactly as a fixed-point integer (see the top of this file). Reads as a
// double.
class ExactSum {
public:
    static constexpr int kFractionBits = 48;
    static constexpr double kMaxAddend = 0x1p46;

    void add(double value) & {
        const double scaled = value * 0x1p48;
        // Fast path: truncation of a value that fits a 64-bit integer.
        if (std::abs(scaled) < 0x1p62)
            raw_ += int64_t(scaled);
        else
            raw_ += wide(scaled);
    }
    // Below this many units in magnitude, an addend may be summed in 64 bits (PixelAccumulator):
    // 2^6 such addends cannot overflow an int64.
    static constexpr double kSmallAddendUnits = 0x1p56;
    // The units add(value) would add, when they are fewer than kSmallAddendUnits in magnitude;
    // false otherwise (NaN included), and then only add(value) adds it.
    static bool smallAddendUnits(double value, int64_t& units) {
        const double scaled = value * 0x1p48;
        if (!(std::abs(scaled) < kSmallAddendUnits)) return false;
        units = int64_t(scaled);
        return true;
    }
    // Adds a sum of addends' units (see smallAddendUnits).
    void addUnits(int64_t units) & {
        PENUMBRA_CHECK(!addOverflows(raw_, units), "a sum stays within 128 bits");
        raw_ += units;
    }
    // A sum that fits 64 bits (nearly all do) converts in one instruction; the 128-bit conversion
    // is a library call. Both round the same integer to the nearest double, so the bits agree.
    double value() const {
        const auto low = int64_t(raw_);
        return (low == raw_ ? double(low) : double(raw_)) * 0x1p-48;
    }
    operator double() const { return value(); }
    // For sums of this render's own samples (a film read from a file is added with tryAdd): each
    // addend is clamped to kMaxAddend, so 2^32 samples stay far below 2^127 units.
    ExactSum& operator+=(const ExactSum& other) & {
        PENUMBRA_CHECK(!addOverflows(raw_, other.raw_), "a sum stays within 128 bits");
        raw_ += other.raw_;
        return *this;
    }
    // Adds `other` unless the 128-bit sum would overflow; false (and unchanged) then.
    bool tryAdd(const ExactSum& other) & { return !__builtin_add_overflow(raw_, other.raw_, &raw_); }
    bool operator==(const ExactSum&) const = default;

    // The 128-bit integer of units itself (Film stores it in two halves).
    __int128 raw() const { return raw_; }
    static ExactSum fromRaw(__int128 raw) {
        ExactSum s;
        s.raw_ = raw;
        return s;
    }

    // Word w (least significant first) of the raw 128-bit integer lies at byte 4 * w of an
    // ExactSum, so a file writer may read the words in place (film_exr.cpp does).
    static constexpr size_t wordOffset(int w) { return size_t(4 * w); }

    // The raw 128-bit integer as four 32-bit words, least significant first (for storage).
    void toWords(uint32_t words[4]) const {
        const auto bits = static_cast<unsigned __int128>(raw_);
        for (int i = 0; i < 4; ++i) words[i] = uint32_t(bits >> (32 * i));
    }
    static ExactSum fromWords(const uint32_t words[4]) {
        unsigned __int128 bits = 0;
        for (int i = 3; i >= 0; --i) bits = (bits << 32) | words[i];
        ExactSum s;
        s.raw_ = static_cast<__int128>(bits);
        return s;
    }

private:
    static bool addOverflows(__int128 a, __int128 b) {
        __int128 sum;
        return __builtin_add_overflow(a, b, &sum);
    }
    static __int128 wide(double scaled) {
        if (!(scaled == scaled)) return 0;  // NaN adds nothing
        const double limit = kMaxAddend * 0x1p48;
        return static_cast<__int128>(std::clamp(scaled, -limit, limit));
    }
    __int128 raw_ = 0;
};

static_assert(std::endian::native == std::endian::little && sizeof(ExactSum) == 16 &&
                  std::is_standard_layout_v<ExactSum>,
              "ExactSum::wordOffset assumes a little-endian 128-bit integer");

struct PixelSums {
    ExactSum radiance[3];         // sum of weight * L
    ExactSum radianceSquared[3];  // sum of weight * L^2
    ExactSum weight;              // sum of weights
    ExactSum albedo[3];           // sum of weight * first-hit albedo (samples that miss add 0)
    ExactSum normal[3];           // sum of weight * first-hit shading normal (samples that miss add 0)
    ExactSum depth;               // sum of weight * first-hit distance, over the samples that hit
    ExactSum hitWeight;           // sum of the weights of the samples that hit something
    uint32_t sampleCount = 0;

    bool operator==(const PixelSums&) const = default;

    // The sums by index, in the order above (the order of the film's EXR channels).
    enum SumIndex : int {
        kRadiance = 0,
        kRadianceSquared = 3,
        kWeight = 6,
        kAlbedo = 7,
        kNormal = 10,
        kDepth = 13,
        kHitWeight = 14,
        kSumCount = 15
    };
    ExactSum& sum(int i) {
        if (i < kRadianceSquared) return radiance[i];
        if (i < kWeight) return radianceSquared[i - kRadianceSquared];
        if (i == kWeight) return weight;
        if (i < kNormal) return albedo[i - kAlbedo];
        if (i < kDepth) return normal[i - kNormal];
        return i == kDepth ? depth : hitWeight;
    }
    const ExactSum& sum(int i) const { return const_cast<PixelSums*>(this)->sum(i); }

    // What one sample adds: addTo(i, addend) for each sum i that it adds to (`aovs` may be null).
    template <typename AddTo>
    static void forEachAddend(Rgb value, float sampleWeight, const FirstHitAovs* aovs, AddTo&& addTo) {
        const double w = sampleWeight;
        for (int c = 0; c < 3; ++c) {
            addTo(kRadiance + c, w * value[c]);
            addTo(kRadianceSquared + c, w * double(value[c]) * value[c]);
        }
        addTo(kWeight, w);
        if (!aovs || !aovs->hit) return;
        for (int c = 0; c < 3; ++c) addTo(kAlbedo + c, w * aovs->albedo[c]);
        addTo(kNormal + 0, w * aovs->normal.x);
        addTo(kNormal + 1, w * aovs->normal.y);
        addTo(kNormal + 2, w * aovs->normal.z);
        addTo(kDepth, w * aovs->distance);
        addTo(kHitWeight, w);
    }

    // Not on a temporary (`&`): Film::at returns a copy, and a sample added to it would be lost.
    void add(Rgb value, float sampleWeight) & { addSample(value, sampleWeight, nullptr); }
    // A sample with its first-hit AOVs.
    void add(Rgb value, float sampleWeight, const FirstHitAovs& aovs) & {
        addSample(value, sampleWeight, &aovs);
    }
    // Adds another film's sums for the same pixel (exact: the order of merges does not matter).
    // False, with this pixel unchanged, when a sum would overflow or the sample count would pass
    // 2^32 - 1 (only crafted or corrupt films get there).
    bool tryMerge(const PixelSums& o) & {
        PixelSums merged = *this;
        for (int i = 0; i < kSumCount; ++i)
            if (!merged.sum(i).tryAdd(o.sum(i))) return false;
        if (__builtin_add_overflow(sampleCount, o.sampleCount, &merged.sampleCount)) return false;
        *this = merged;
        return true;
    }
    void merge(const PixelSums& o) & {
        for (int c = 0; c < 3; ++c) {
            radiance[c] += o.radiance[c];
            radianceSquared[c] += o.radianceSquared[c];
            albedo[c] += o.albedo[c];
            normal[c] += o.normal[c];
        }
        weight += o.weight;
        depth += o.depth;
        hitWeight += o.hitWeight;
        sampleCount += o.sampleCount;
    }

    Rgb mean() const {
        const double w = weight;
        if (w <= 0) return Rgb(0.0f);
        return {float(radiance[0] / w), float(radiance[1] / w), float(radiance[2] / w)};
    }
    // Sample variance of the mean estimate, per channel (0 with fewer than two samples).
    Rgb varianceOfMean() const;
    // Mean first-hit albedo and shading normal over all samples (a miss counts as 0; the mean
    // normal is not renormalized), and mean first-hit distance over the samples that hit
    // (+infinity when none did).
    Rgb meanAlbedo() const;
    Vec3f meanNormal() const;
    float meanDepth() const;

private:
    void addSample(Rgb value, float sampleWeight, const FirstHitAovs* aovs) {
        forEachAddend(value, sampleWeight, aovs, [this](int i, double addend) { sum(i).add(addend); });
        ++sampleCount;
    }
};

// A film's sums in memory, 130 B a pixel (it was 256 with every sum 128 bits wide): each sum's low
// 64 bits, the beauty's seven (radiance, its square, weight) and the sample count in one 64-byte
// line, the eight AOV sums in another array, and the high 64 bits of a sum only where it has
// outgrown the low (film/high_words.h: 2 B a pixel of block pointers). Pixels are read out as PixelSums, to
// the same 128-bit integers: merges and resumes stay exact (bench/README.md, "The film's memory").
class Film {
public:
    // Bytes a pixel needs beside its sums when the film is written: the EXR's 14 floats.
    static constexpr size_t kOutputBytesPerPixel = 14 * sizeof(float);
    static constexpr int kBeautySums = PixelSums::kAlbedo;  // radiance, its square, the weight
    static constexpr int kAovSums = PixelSums::kSumCount - kBeautySums;

    // Throws InputError when the film, and the buffer to write it, would not fit in the memory
    // available now (an impossible resolution, or a file that claims one), rather than failing
    // somewhere in the allocation.
    Film(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    // Bytes a pixel takes in memory, high words aside (their block pointers included).
    static constexpr size_t bytesPerPixel() {
        return sizeof(BeautyPixel) + sizeof(AovPixel) + HighWords::kPointerBytesPerPixel;
    }

    // A pixel's sums, to their full 128 bits.
    PixelSums at(int x, int y) const;
    uint32_t sampleCount(int x, int y) const { return beauty_[index(x, y)].sampleCount; }

    // Adds one sample as PixelSums::add does (`aovs` may be null).
    void add(int x, int y, Rgb value, float sampleWeight, const FirstHitAovs* aovs = nullptr);
    // Adds units[i] 2^-48 units to sum i, and `samples` to the sample count (PixelAccumulator).
    void addUnits(int x, int y, const int64_t (&units)[PixelSums::kSumCount], uint32_t samples);
    // Adds one addend to sum `sum` exactly as ExactSum::add adds it.
    void addAddend(int x, int y, int sum, double addend);
    // Replaces a pixel's sums (a film read from a file).
    void set(int x, int y, const PixelSums& sums);

    // Mean radiance, row-major RGB triples, top row first.
    std::vector<float> meanRgb() const;
    uint64_t totalSamples() const;
    // Adds `other`'s sums pixel by pixel (same size required; exact, in any order). Throws
    // InputError naming the pixel when a sum or a sample count would overflow (PixelSums::tryMerge).
    void merge(const Film& other);
    // True when every sum of every pixel is the same bit for bit.
    bool identicalTo(const Film& other) const;

    // For a writer that reads the stored words in place: the low 64 bits of sum `sum` of pixel
    // (0, 0) and the bytes from one pixel's to the next's; the sample counts likewise.
    const int64_t* lowWords(int sum) const {
        return sum < kBeautySums ? beauty_.data()->low + sum : aovs_.data()->low + (sum - kBeautySums);
    }
    static constexpr size_t lowWordStride(int sum) {
        return sum < kBeautySums ? sizeof(BeautyPixel) : sizeof(AovPixel);
    }
    const uint32_t* sampleCounts() const { return &beauty_.data()->sampleCount; }
    static constexpr size_t sampleCountStride() { return sizeof(BeautyPixel); }
    // False when every pixel's sum `sum` lies within its low 64 bits.
    bool hasHighWords(int sum) const { return highWords_.anyAllocated(sum); }

private:
    struct BeautyPixel {
        int64_t low[kBeautySums] = {};
        uint32_t sampleCount = 0;
    };
    struct AovPixel {
        int64_t low[kAovSums] = {};
    };
    static_assert(sizeof(BeautyPixel) == 64 && sizeof(AovPixel) == 64,
                  "a pixel's sums fill whole cache lines");

    size_t index(int x, int y) const {
        PENUMBRA_CHECK(x >= 0 && x < width_ && y >= 0 && y < height_, "a pixel lies in the film");
        return size_t(y) * size_t(width_) + size_t(x);
    }
    int64_t& low(size_t pixel, int sum) {
        return sum < kBeautySums ? beauty_[pixel].low[sum] : aovs_[pixel].low[sum - kBeautySums];
    }
    int64_t low(size_t pixel, int sum) const { return const_cast<Film*>(this)->low(pixel, sum); }
    // Adds to a sum's low word, counting a wrap in its high word: the sum is high * 2^64 + low.
    void addToLow(size_t pixel, int sum, int64_t units) {
        if (__builtin_add_overflow(low(pixel, sum), units, &low(pixel, sum)))
            highWords_.at(pixel, sum) += units > 0 ? 1 : -1;
    }
    PixelSums sums(size_t pixel) const;
    void set(size_t pixel, const PixelSums& sums);
    __int128 sum(size_t pixel, int sum) const;
    void setSum(size_t pixel, int sum, __int128 value);
    void addToSum(size_t pixel, int sum, __int128 value);

    int width_, height_;
    // On huge pages: a 512x512 film is 32 MiB, which by 4 KiB pages costs 8,192 page faults
    // (core/huge_page_allocator.h).
    std::vector<BeautyPixel, HugePageAllocator<BeautyPixel>> beauty_;
    std::vector<AovPixel, HugePageAllocator<AovPixel>> aovs_;
    HighWords highWords_;
};

}  // namespace penumbra
