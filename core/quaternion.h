// Unit quaternions for rotations that are interpolated as rotations (motion blur keys).
#pragma once

#include <cmath>

#include "core/transform.h"
#include "core/vec.h"

namespace penumbra {

struct Quaternion {
    float w = 1.0f;
    Vec3f v{0.0f, 0.0f, 0.0f};  // (i, j, k)

    static Quaternion fromAxisAngle(Vec3f axis, float angleDegrees) {
        const Vec3f a = normalize(axis);
        const double half = double(angleDegrees) * 3.14159265358979323846 / 360.0;
        const float s = float(std::sin(half));
        return {float(std::cos(half)), a * s};
    }
    float dot(const Quaternion& o) const { return w * o.w + penumbra::dot(v, o.v); }
    Quaternion operator-() const { return {-w, -v}; }
    Quaternion normalized() const {
        const float n = std::sqrt(dot(*this));
        return {w / n, v / n};
    }
    // Hamilton product: applying `o` first, then this.
    Quaternion operator*(const Quaternion& o) const {
        return {w * o.w - penumbra::dot(v, o.v), o.v * w + v * o.w + cross(v, o.v)};
    }

    // The rotation matrix (row-major 3x3 embedded in a Matrix4).
    Matrix4 toMatrix() const {
        const float x = v.x, y = v.y, z = v.z;
        Matrix4 m = Matrix4::identity();
        m.m[0][0] = 1 - 2 * (y * y + z * z);
        m.m[0][1] = 2 * (x * y - z * w);
        m.m[0][2] = 2 * (x * z + y * w);
        m.m[1][0] = 2 * (x * y + z * w);
        m.m[1][1] = 1 - 2 * (x * x + z * z);
        m.m[1][2] = 2 * (y * z - x * w);
        m.m[2][0] = 2 * (x * z - y * w);
        m.m[2][1] = 2 * (y * z + x * w);
        m.m[2][2] = 1 - 2 * (x * x + y * y);
        return m;
    }
};

// Spherical linear interpolation along the shorter arc; t in [0, 1].
inline Quaternion slerp(const Quaternion& a, Quaternion b, float t) {
    float cosTheta = a.dot(b);
    if (cosTheta < 0.0f) {
        b = -b;
        cosTheta = -cosTheta;
    }
    if (cosTheta > 0.9995f) {  // nearly parallel: normalized lerp is exact to float precision
        return Quaternion{a.w + (b.w - a.w) * t, a.v + (b.v - a.v) * t}.normalized();
    }
    const float theta = std::acos(std::min(cosTheta, 1.0f));
    const float sinTheta = std::sin(theta);
    const float wa = std::sin((1.0f - t) * theta) / sinTheta, wb = std::sin(t * theta) / sinTheta;
    return Quaternion{a.w * wa + b.w * wb, a.v * wa + b.v * wb}.normalized();
}

}  // namespace penumbra
