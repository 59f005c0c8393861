// Double-precision points and 4x4 matrices for pbrt's transform stack: a scene's transforms are
// composed (often dozens deep) and inverted in double, and rounded to float once, when the scene
// is built.
#pragma once

#include <array>
#include <cmath>
#include <optional>

namespace penumbra::pbrt {

struct Vec2d {
    double x = 0, y = 0;
};

struct Vec3d {
    double x = 0, y = 0, z = 0;
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d operator*(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3d cross(Vec3d a, Vec3d b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3d a) { return std::sqrt(dot(a, a)); }
inline Vec3d normalize(Vec3d a) { return a * (1.0 / length(a)); }

// Row-major, applied to column vectors: the translation is the last column.
struct Matrix4d {
    std::array<std::array<double, 4>, 4> m{};

    static Matrix4d identity() {
        Matrix4d r;
        for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
        return r;
    }
    Matrix4d operator*(const Matrix4d& o) const {
        Matrix4d r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                for (int k = 0; k < 4; ++k) r.m[i][j] += m[i][k] * o.m[k][j];
        return r;
    }
    bool operator==(const Matrix4d& o) const { return m == o.m; }
    Matrix4d transposed() const {
        Matrix4d r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) r.m[i][j] = m[j][i];
        return r;
    }
    Vec3d applyPoint(Vec3d p) const {
        const double w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
        const Vec3d r{m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                      m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                      m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
        return w == 1.0 ? r : r * (1.0 / w);
    }
    Vec3d applyVector(Vec3d v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    // The determinant of the upper 3x3: negative when the transform mirrors.
    double determinant3() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    bool isAffine() const { return m[3][0] == 0 && m[3][1] == 0 && m[3][2] == 0 && m[3][3] == 1; }

    // Gauss-Jordan with partial pivoting; empty when singular or not finite.
    std::optional<Matrix4d> inverse() const {
        std::array<std::array<double, 8>, 4> a{};
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) a[i][j] = m[i][j];
            a[i][4 + i] = 1.0;
        }
        for (int c = 0; c < 4; ++c) {
            int pivot = c;
            for (int r = c + 1; r < 4; ++r)
                if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
            if (!(std::abs(a[pivot][c]) > 1e-300) || !std::isfinite(a[pivot][c])) return std::nullopt;
            std::swap(a[c], a[pivot]);
            const double inv = 1.0 / a[c][c];
            for (double& v : a[c]) v *= inv;
            for (int r = 0; r < 4; ++r)
                if (r != c && a[r][c] != 0.0) {
                    const double f = a[r][c];
                    for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
                }
        }
        Matrix4d r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) r.m[i][j] = a[i][4 + j];
        for (const auto& row : r.m)
            for (double v : row)
                if (!std::isfinite(v)) return std::nullopt;
        return r;
    }
};

}  // namespace penumbra::pbrt
