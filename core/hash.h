// Integer hashing for deterministic sample values: every random number in penumbra is a hash of
// (seed, pixel, sample index, dimension), never the state of a per-thread generator.
#pragma once

#include <cstdint>

namespace penumbra {

// 64-bit finalizer of MurmurHash3 / SplitMix64: a bijection with full avalanche.
inline constexpr uint64_t mix64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

// The terms of hashCombine's sum that depend on the seed alone, for callers that combine one seed
// with many values: hashCombineWithSeedTerms(seed, hashCombineSeedTerms(seed), value) is
// hashCombine(seed, value).
inline constexpr uint64_t hashCombineSeedTerms(uint64_t seed) {
    return 0x9e3779b97f4a7c15ULL + (seed << 6) + (seed >> 2);
}
inline constexpr uint64_t hashCombineWithSeedTerms(uint64_t seed, uint64_t seedTerms, uint64_t value) {
    return mix64(seed ^ (value + seedTerms));
}

// Order-dependent combination of several words into one well-mixed 64-bit value.
inline constexpr uint64_t hashCombine(uint64_t seed, uint64_t value) {
    return hashCombineWithSeedTerms(seed, hashCombineSeedTerms(seed), value);
}

template <typename... Words>
inline constexpr uint64_t hashWords(uint64_t first, Words... rest) {
    uint64_t h = mix64(first + 0x9e3779b97f4a7c15ULL);
    ((h = hashCombine(h, uint64_t(rest))), ...);
    return h;
}

// A float uniformly in [0, 1) from the top 24 bits of a 32-bit value; never returns 1.
inline constexpr float bitsToUnitFloat(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

inline constexpr uint32_t reverseBits32(uint32_t x) {
    x = __builtin_bswap32(x);  // bytes in one instruction, then the bits within each byte
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    return x;
}

}  // namespace penumbra
