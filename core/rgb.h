// Linear RGB radiance / reflectance triple (scene-linear Rec.709 primaries).
#pragma once

#include <algorithm>
#include <cmath>

namespace penumbra {

struct Rgb {
    float r = 0, g = 0, b = 0;
    constexpr Rgb() = default;
    constexpr explicit Rgb(float v) : r(v), g(v), b(v) {}
    constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
    constexpr float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    Rgb& operator+=(Rgb o) {
        r += o.r;
        g += o.g;
        b += o.b;
        return *this;
    }
    Rgb& operator*=(Rgb o) {
        r *= o.r;
        g *= o.g;
        b *= o.b;
        return *this;
    }
    Rgb& operator*=(float s) {
        r *= s;
        g *= s;
        b *= s;
        return *this;
    }
    constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
    float maxComponent() const { return std::max(r, std::max(g, b)); }
    float minComponent() const { return std::min(r, std::min(g, b)); }
    // Rec.709 luminance, used for light power and Russian roulette.
    constexpr float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
    float average() const { return (r + g + b) / 3.0f; }
    bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

inline constexpr Rgb operator+(Rgb a, Rgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline constexpr Rgb operator-(Rgb a, Rgb b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
inline constexpr Rgb operator*(Rgb a, Rgb b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
inline constexpr Rgb operator*(Rgb a, float s) { return {a.r * s, a.g * s, a.b * s}; }
inline constexpr Rgb operator*(float s, Rgb a) { return a * s; }
inline constexpr Rgb operator/(Rgb a, float s) { return a * (1.0f / s); }
inline constexpr bool operator==(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

}  // namespace penumbra
