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
//    render, which makes resume and convergence ladders exact.
#pragma once

#include <cstdint>
#include <string_view>

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
    LightChoice,      // 1D: which light next-event estimation samples
    LightPosition,    // 2D: point on that light
    BsdfLobe,         // 1D: which lobe of the material is sampled
    BsdfDirection,    // 2D: direction within the lobe
    RussianRoulette,  // 1D: survival decision
    Count
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

// Second dimension of the Sobol sequence (primitive polynomial x + 1).
inline constexpr uint32_t sobolSecondDimension(uint32_t index) {
    uint32_t result = 0;
    for (uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1)
        if (index & 1u) result ^= v;
    return result;
}

}  // namespace detail

// The sample values of one (pixel, sample index) under a given sampler and seed.
class PixelSample {
public:
    PixelSample(SamplerKind kind, uint64_t seed, uint64_t pixelIndex, uint32_t sampleIndex)
        : kind_(kind), pixelKey_(hashWords(seed, pixelIndex)), sampleIndex_(sampleIndex) {}

    float get1D(Dim dim, uint32_t bounce = 0) const {
        const uint64_t key = dimensionKey(dim, bounce);
        if (kind_ == SamplerKind::Independent)
            return bitsToUnitFloat(uint32_t(hashWords(key, sampleIndex_)));
        const uint32_t index = shuffledIndex(key);
        return bitsToUnitFloat(detail::nestedUniformScramble(reverseBits32(index), uint32_t(key >> 32)));
    }

    Vec2f get2D(Dim dim, uint32_t bounce = 0) const {
        const uint64_t key = dimensionKey(dim, bounce);
        if (kind_ == SamplerKind::Independent) {
            const uint64_t bits = hashWords(key, sampleIndex_);
            return {bitsToUnitFloat(uint32_t(bits)), bitsToUnitFloat(uint32_t(bits >> 32))};
        }
        const uint32_t index = shuffledIndex(key);
        const uint64_t scrambleSeeds = mix64(key);
        return {bitsToUnitFloat(detail::nestedUniformScramble(reverseBits32(index), uint32_t(scrambleSeeds))),
                bitsToUnitFloat(detail::nestedUniformScramble(detail::sobolSecondDimension(index),
                                                              uint32_t(scrambleSeeds >> 32)))};
    }

    uint32_t sampleIndex() const { return sampleIndex_; }

private:
    uint64_t dimensionKey(Dim dim, uint32_t bounce) const {
        return hashCombine(pixelKey_, uint64_t(bounce) * uint64_t(Dim::Count) + uint64_t(dim));
    }
    // The per-dimension shuffle: a permutation of every aligned power-of-two block of indices.
    uint32_t shuffledIndex(uint64_t key) const {
        return detail::nestedUniformScramble(sampleIndex_, uint32_t(key));
    }

    SamplerKind kind_;
    uint64_t pixelKey_;
    uint32_t sampleIndex_;
};

}  // namespace penumbra
