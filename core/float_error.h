// Bounds on floating-point rounding error (Pharr, Jakob and Humphreys, "Physically Based
// Rendering", 4th ed., section 6.8): gamma(n) bounds the relative error of n rounded operations,
// and stepping a float by one representable value rounds a result conservatively.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace penumbra {

// gamma(n) = n u / (1 - n u), u = 2^-24 (float's unit roundoff).
constexpr float gamma(int n) {
    constexpr float u = 0x1p-24f;
    return float(n) * u / (1.0f - float(n) * u);
}

// The next float above v (-0 steps as +0); infinity and NaN stay.
inline float nextFloatUp(float v) {
    if (std::isinf(v) && v > 0.0f) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v >= 0.0f ? bits + 1 : bits - 1;
    return std::bit_cast<float>(bits);
}

// The next float below v (+0 steps as -0); -infinity and NaN stay.
inline float nextFloatDown(float v) {
    if (std::isinf(v) && v < 0.0f) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v > 0.0f ? bits - 1 : bits + 1;
    return std::bit_cast<float>(bits);
}

}  // namespace penumbra
