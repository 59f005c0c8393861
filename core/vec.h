// Small fixed-size vectors used everywhere: Vec2f, Vec3f and their arithmetic.
#pragma once

#include <algorithm>
#include <cmath>

namespace penumbra {

struct Vec2f {
    float x = 0, y = 0;
    constexpr Vec2f() = default;
    constexpr Vec2f(float x_, float y_) : x(x_), y(y_) {}
    constexpr float operator[](int i) const { return i == 0 ? x : y; }
};

inline constexpr Vec2f operator+(Vec2f a, Vec2f b) { return {a.x + b.x, a.y + b.y}; }
inline constexpr Vec2f operator-(Vec2f a, Vec2f b) { return {a.x - b.x, a.y - b.y}; }
inline constexpr Vec2f operator*(Vec2f a, float s) { return {a.x * s, a.y * s}; }
inline constexpr Vec2f operator*(float s, Vec2f a) { return a * s; }

struct Vec3f {
    float x = 0, y = 0, z = 0;
    constexpr Vec3f() = default;
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3f& operator+=(Vec3f b) {
        x += b.x;
        y += b.y;
        z += b.z;
        return *this;
    }
    Vec3f& operator-=(Vec3f b) {
        x -= b.x;
        y -= b.y;
        z -= b.z;
        return *this;
    }
    Vec3f& operator*=(float s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
};

inline constexpr Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline constexpr Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline constexpr Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
inline constexpr Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline constexpr Vec3f operator*(float s, Vec3f a) { return a * s; }
inline constexpr Vec3f operator/(Vec3f a, float s) { return a * (1.0f / s); }
inline constexpr bool operator==(Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

inline constexpr float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline constexpr Vec3f cross(Vec3f a, Vec3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
inline constexpr float lengthSquared(Vec3f a) { return dot(a, a); }
inline Vec3f normalize(Vec3f a) { return a / length(a); }
inline Vec3f abs(Vec3f a) { return {std::abs(a.x), std::abs(a.y), std::abs(a.z)}; }
inline Vec3f min(Vec3f a, Vec3f b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3f max(Vec3f a, Vec3f b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
// Each coordinate of `a` times the same coordinate of `b`.
inline constexpr Vec3f scaleComponents(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline float maxComponent(Vec3f a) { return std::max(a.x, std::max(a.y, a.z)); }
inline bool isFinite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
// The vector flipped, if needed, to lie in the hemisphere of `reference`.
inline Vec3f faceForward(Vec3f v, Vec3f reference) { return dot(v, reference) < 0 ? -v : v; }

}  // namespace penumbra
