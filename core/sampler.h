// Sample values identified by (seed, pixel, sample index, named dimension).
//
// Because a value depends on nothing but that identity, images are bit-identical whatever the
// thread count or tile order, any range of samples [a, b) can be rendered anywhere, and partial
// renders merge exactly.
//
// Two samplers:
//  - independent: each value is a hash of its identity (the baseline for convergence studies);
//  - stratified: per pixel and per named dimension, an Owen-scrambled Sobol (0,2)-sequence with
//    a per-dimension nested-uniform shuffle of the sample index (Burley, "Practical Hash-based
//    Owen Scrambling", JCGT 2020). Every power-of-two prefix of a pixel's samples puts exactly
//    one sample in each stratum of each dimension (1D: N intervals; 2D: every elementary interval
//    of area 1/N, the sqrt(N) x sqrt(N) grid included when N is a power of 4), sample counts
//    that are not powers of two are unions of such stratified blocks, and the shuffle decorrelates
//    the dimensions so that, e.g., lens position does not follow pixel position.
//    The pattern is progressive: the first 64 samples of a 256-sample render are a 64-sample
//    render, which makes resume and convergence ladders exact. One dimension is drawn jointly
//    with another instead (get1DJointWith): the camera's time, as the third Sobol coordinate of
//    its position in the pixel.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#if defined(__SSE4_1__)
#include <smmintrin.h>
#include <tmmintrin.h>
#endif

#include "core/hash.h"
#include "core/vec.h"

namespace penumbra {

enum class SamplerKind : uint8_t { Stratified, Independent };

std::string_view samplerKindName(SamplerKind kind);

// The named sample dimensions. Camera dimensions are drawn once per sample; the others once per
// bounce (vertex) of the path. Never index samples by hand-counted offsets.
enum class Dim : uint32_t {
    Pixel,            // 2D: position within the pixel's filter footprint
    Lens,             // 2D: position on the lens aperture
    Time,             // 1D: instant within the shutter
    LightPosition,    // 2D: which light next-event estimation samples (x, reused: LightSet::choose) and the
                      // point on it
    BsdfLobe,         // 1D: which lobe of the material is sampled
    BsdfDirection,    // 2D: direction within the lobe
    RussianRoulette,  // 1D: survival decision
    Count
};

// The dimensions of participating media (renderer/volumetric_path_integrator.h), apart from Dim:
// their "bounce" is the path's segment (each ray between two vertices or boundary crossings), not
// its scattering depth, and their keys lie apart from Dim's, whose keys (and so the images of
// scenes without media) stay as they were.
enum class MediumDim : uint32_t {
    Channel,              // 1D (segment 0): the colour channel whose majorant samples distances (hero)
    Distance,             // 1D: the first free-flight distance along the segment; a SampleStream the rest
    Event,                // 1D: the first collision's choice (absorb, scatter, null); a SampleStream the rest
    ShadowTransmittance,  // SampleStream only: ratio tracking's Russian roulette along a shadow ray
    EquiangularDistance,  // 1D: the distance of the segment's equiangular light sample
    EquiangularLight,  // SampleStream only: that sample's light and point (2 values), then its shadow ray's
    Count
};

// Uniform values without end for a (dimension, segment) of one sample: delta tracking along a ray
// makes as many collisions as it meets. Hashed from the dimension's key and a counter (pbrt-v4
// seeds an RNG from the ray instead), so deterministic like every other sample value.
class SampleStream {
public:
    explicit SampleStream(uint64_t key) : key_(key) {}
    float next() { return bitsToUnitFloat(uint32_t(hashWords(key_, counter_++) >> 32)); }

private:
    uint64_t key_;
    uint64_t counter_ = 0;
};

namespace detail {

// Laine-Karras permutation (the hash Burley 2020 builds on): Owen scrambling of bit-reversed input.
inline constexpr uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

inline constexpr uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
    return reverseBits32(laineKarrasPermutation(reverseBits32(x), seed));
}

// A dimension of the Sobol sequence from its 32 direction numbers (the columns of its generator
// matrix, most significant bit first): the XOR of the direction numbers of the index's set bits,
// looked up a byte at a time, bit-reversed (the form Owen scrambling works on, which saves a
// reversal per sample).
struct ReversedSobolDimension {
    uint32_t byByte[4][256];
    constexpr explicit ReversedSobolDimension(const std::array<uint32_t, 32>& direction) : byByte{} {
        for (int k = 0; k < 4; ++k)
            for (uint32_t b = 0; b < 256; ++b) {
                uint32_t value = 0;
                for (int j = 0; j < 8; ++j)
                    if (b & (1u << j)) value ^= reverseBits32(direction[8 * k + j]);
                byByte[k][b] = value;
            }
    }
    constexpr uint32_t operator()(uint32_t index) const {
        return byByte[0][index & 0xffu] ^ byByte[1][(index >> 8) & 0xffu] ^ byByte[2][(index >> 16) & 0xffu] ^
               byByte[3][index >> 24];
    }
};

// The second dimension's direction numbers (primitive polynomial x + 1).
constexpr std::array<uint32_t, 32> sobolSecondDirections() {
    std::array<uint32_t, 32> direction{};
    for (uint32_t bit = 0, v = 1u << 31; bit < 32; ++bit, v ^= v >> 1) direction[bit] = v;
    return direction;
}

// The third's (Joe and Kuo's d = 3: primitive polynomial x^2 + x + 1, initial direction numbers
// m = 1, 3). With the first two it makes every power-of-two prefix a (1, m, 3)-net: every
// elementary box of volume 2/N holds two points.
constexpr std::array<uint32_t, 32> sobolThirdDirections() {
    uint32_t m[33] = {0, 1, 3};
    for (int k = 3; k <= 32; ++k) m[k] = (2u * m[k - 1]) ^ (4u * m[k - 2]) ^ m[k - 2];
    std::array<uint32_t, 32> direction{};
    for (int k = 1; k <= 32; ++k) direction[size_t(k - 1)] = m[k] << (32 - k);
    return direction;
}

inline constexpr ReversedSobolDimension kReversedSobolSecondDimension{sobolSecondDirections()};
inline constexpr ReversedSobolDimension kReversedSobolThirdDimension{sobolThirdDirections()};

inline constexpr uint32_t reversedSobolSecondDimension(uint32_t index) {
    return kReversedSobolSecondDimension(index);
}
inline constexpr uint32_t reversedSobolThirdDimension(uint32_t index) {
    return kReversedSobolThirdDimension(index);
}

// The two coordinates of a stratified 2D sample from its shuffled index: the first and second
// Sobol dimensions of `index`, each Owen-scrambled with its own seed, as floats in [0, 1).
inline Vec2f scrambledSobolPairScalar(uint32_t index, uint32_t xSeed, uint32_t ySeed) {
    return {
        bitsToUnitFloat(reverseBits32(laineKarrasPermutation(index, xSeed))),
        bitsToUnitFloat(reverseBits32(laineKarrasPermutation(reversedSobolSecondDimension(index), ySeed)))};
}

// The same values, with x and y in two lanes of one SSE register where SSE4.1 is there (the
// x86-64-v3 build): the hash's multiplies, the bit reversal (a byte shuffle and two nibble
// look-ups) and the conversion to float once for both. Integer operations, so the same bits.
inline Vec2f scrambledSobolPair(uint32_t index, uint32_t xSeed, uint32_t ySeed) {
#if defined(__SSE4_1__)
    __m128i x = _mm_add_epi32(_mm_setr_epi32(int(index), int(reversedSobolSecondDimension(index)), 0, 0),
                              _mm_setr_epi32(int(xSeed), int(ySeed), 0, 0));
    for (const uint32_t factor : {0x6c50b47cu, 0xb82f1e52u, 0xc7afe638u, 0x8d22f6e6u})
        x = _mm_xor_si128(x, _mm_mullo_epi32(x, _mm_set1_epi32(int(factor))));
    // Reversal: bytes in reverse order within each lane, then each byte's bits from two nibbles.
    x = _mm_shuffle_epi8(x, _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12));
    const __m128i lowNibbles = _mm_set1_epi8(0x0f);
    const __m128i reversedAsHigh = _mm_setr_epi8(0x00, 0x80, 0x40, 0xc0, 0x20, 0xa0, 0x60, 0xe0, 0x10, 0x90,
                                                 0x50, 0xd0, 0x30, 0xb0, 0x70, 0xf0);
    const __m128i reversedAsLow =
        _mm_srli_epi16(reversedAsHigh, 4);  // no bits cross a byte: the low nibbles are 0
    x = _mm_or_si128(_mm_shuffle_epi8(reversedAsHigh, _mm_and_si128(x, lowNibbles)),
                     _mm_shuffle_epi8(reversedAsLow, _mm_and_si128(_mm_srli_epi16(x, 4), lowNibbles)));
    const __m128 unit = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srli_epi32(x, 8)), _mm_set1_ps(0x1p-24f));
    return {_mm_cvtss_f32(unit), _mm_cvtss_f32(_mm_shuffle_ps(unit, unit, _MM_SHUFFLE(1, 1, 1, 1)))};
#else
    return scrambledSobolPairScalar(index, xSeed, ySeed);
#endif
}

}  // namespace detail

// The part of a sample's identity that all samples of a pixel share, (seed, pixel), hashed: made
// once per pixel by the render loop rather than once per sample.
struct PixelKey {
    uint64_t value;
    static PixelKey of(uint64_t seed, uint64_t pixelIndex) { return {hashWords(seed, pixelIndex)}; }
};

// The sample values of one (pixel, sample index) under a given sampler and seed.
class PixelSample {
public:
    PixelSample(SamplerKind kind, uint64_t seed, uint64_t pixelIndex, uint32_t sampleIndex)
        : PixelSample(kind, PixelKey::of(seed, pixelIndex), sampleIndex) {}
    PixelSample(SamplerKind kind, PixelKey pixel, uint32_t sampleIndex)
        : kind_(kind),
          pixelKey_(pixel.value),
          sampleIndex_(sampleIndex),
          reversedSampleIndex_(reverseBits32(sampleIndex)),
          pixelKeyTerms_(hashCombineSeedTerms(pixel.value)) {}

    float get1D(Dim dim, uint32_t bounce = 0) const {
        if (frozen_ & dimBit(dim)) [[unlikely]]
            return 0.5f;
        const uint64_t key = dimensionKey(dim, bounce);
        if (kind_ == SamplerKind::Independent) return bitsToUnitFloat(uint32_t(hashWords(key, sampleIndex_)));
        // The first Sobol dimension is the bit-reversed index, so its Owen scrambling reduces to
        // reverse(permute(index)).
        const uint32_t index = shuffledIndex(key);
        return bitsToUnitFloat(reverseBits32(detail::laineKarrasPermutation(index, uint32_t(key >> 32))));
    }
    // A medium dimension's value at `segment` (never frozen), drawn as get1D's.
    float get1D(MediumDim dim, uint32_t segment) const {
        const uint64_t key = mediumDimensionKey(dim, segment);
        if (kind_ == SamplerKind::Independent) return bitsToUnitFloat(uint32_t(hashWords(key, sampleIndex_)));
        const uint32_t index = shuffledIndex(key);
        return bitsToUnitFloat(reverseBits32(detail::laineKarrasPermutation(index, uint32_t(key >> 32))));
    }

    Vec2f get2D(Dim dim, uint32_t bounce = 0) const {
        if (frozen_ & dimBit(dim)) [[unlikely]]
            return {0.5f, 0.5f};
        return get2DUnfrozen(dim, bounce);
    }
    // The value get2D gives when `dim` is not frozen, whether it is or not.
    Vec2f get2DUnfrozen(Dim dim, uint32_t bounce = 0) const {
        const uint64_t key = dimensionKey(dim, bounce);
        if (kind_ == SamplerKind::Independent) {
            const uint64_t bits = hashWords(key, sampleIndex_);
            return {bitsToUnitFloat(uint32_t(bits)), bitsToUnitFloat(uint32_t(bits >> 32))};
        }
        // Three seeds from the dimension's key: the shuffle (low half), x's scramble (high half) and
        // y's scramble (the high half of the key times an odd constant, another well-mixed word).
        const uint32_t yScrambleSeed = uint32_t((key * 0x9e3779b97f4a7c15ULL) >> 32);
        return detail::scrambledSobolPair(shuffledIndex(key), uint32_t(key >> 32), yScrambleSeed);
    }

    // A 1D value for `dim` (at bounce 0) stratified jointly with `pairDim`'s 2D value: the third
    // Sobol coordinate of the point whose first two are pairDim's (the same shuffled index, its
    // own scramble), so that the three make a (1, m, 3)-net in every power-of-two prefix. The
    // camera draws the shutter time this way: a moving edge's coverage of a pixel depends on the
    // position in the pixel and the time together, and the three-dimensional strata follow it
    // where a time shuffled on its own would not. The independent sampler's value is get1D's.
    float get1DJointWith(Dim pairDim, Dim dim) const {
        if (frozen_ & dimBit(dim)) [[unlikely]]
            return 0.5f;
        const uint64_t key = dimensionKey(dim, 0);
        if (kind_ == SamplerKind::Independent) return bitsToUnitFloat(uint32_t(hashWords(key, sampleIndex_)));
        const uint32_t index = shuffledIndex(dimensionKey(pairDim, 0));
        return bitsToUnitFloat(reverseBits32(
            detail::laineKarrasPermutation(detail::reversedSobolThirdDimension(index), uint32_t(key >> 32))));
    }

    // The stream of uniform values of (dim, segment) for this sample (SampleStream).
    SampleStream stream(MediumDim dim, uint32_t segment) const {
        return SampleStream(hashWords(mediumDimensionKey(dim, segment), sampleIndex_, uint64_t(kind_)));
    }
    uint32_t sampleIndex() const { return sampleIndex_; }

    // Freezing: the dimensions in `mask` (a set of dimBit(Dim)) return the centre of their domain,
    // 0.5 or (0.5, 0.5), at every bounce, so that a convergence study can attribute noise to one
    // effect (`penumbra converge --freeze lens|time|light|pixel`).
    static constexpr uint32_t dimBit(Dim dim) { return 1u << uint32_t(dim); }
    void freeze(uint32_t mask) { frozen_ = mask; }
    bool isFrozen(Dim dim) const { return (frozen_ & dimBit(dim)) != 0; }

private:
    // hashCombine(pixelKey_, bounce * Count + dim), its terms that depend on the pixel alone
    // computed once per sample.
    uint64_t dimensionKey(Dim dim, uint32_t bounce) const {
        return hashCombineWithSeedTerms(pixelKey_, pixelKeyTerms_,
                                        uint64_t(bounce) * uint64_t(Dim::Count) + uint64_t(dim));
    }
    // The media's keys, from 2^40 on: apart from every (dim, bounce) of Dim's.
    uint64_t mediumDimensionKey(MediumDim dim, uint32_t segment) const {
        return hashCombineWithSeedTerms(
            pixelKey_, pixelKeyTerms_,
            (uint64_t(1) << 40) + uint64_t(segment) * uint64_t(MediumDim::Count) + uint64_t(dim));
    }
    // The per-dimension shuffle: a permutation of every aligned power-of-two block of indices.
    uint32_t shuffledIndex(uint64_t key) const {
        return reverseBits32(detail::laineKarrasPermutation(reversedSampleIndex_, uint32_t(key)));
    }

    SamplerKind kind_;
    uint64_t pixelKey_;
    uint32_t sampleIndex_;
    uint32_t reversedSampleIndex_;
    uint64_t pixelKeyTerms_;  // hashCombineSeedTerms(pixelKey_)
    uint32_t frozen_ = 0;
};

}  // namespace penumbra
