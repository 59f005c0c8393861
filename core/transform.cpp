#include "core/transform.h"

#include <cmath>
#include <numbers>

namespace penumbra {

Matrix4 Matrix4::identity() {
    Matrix4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0f;
    return r;
}

Matrix4 Matrix4::operator*(const Matrix4& o) const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k) sum += double(m[i][k]) * double(o.m[k][j]);
            r.m[i][j] = float(sum);
        }
    return r;
}

Matrix4 Matrix4::transposed() const {
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = m[j][i];
    return r;
}

// Gauss-Jordan elimination with partial pivoting, in double precision.
std::optional<Matrix4> Matrix4::inverse() const {
    double a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            if (!std::isfinite(m[i][j])) return std::nullopt;
            a[i][j] = m[i][j];
            a[i][j + 4] = (i == j) ? 1.0 : 0.0;
        }
    for (int col = 0; col < 4; ++col) {
        int pivot = col;
        for (int row = col + 1; row < 4; ++row)
            if (std::abs(a[row][col]) > std::abs(a[pivot][col])) pivot = row;
        if (std::abs(a[pivot][col]) < 1e-12) return std::nullopt;
        if (pivot != col)
            for (int j = 0; j < 8; ++j) std::swap(a[col][j], a[pivot][j]);
        const double inv = 1.0 / a[col][col];
        for (int j = 0; j < 8; ++j) a[col][j] *= inv;
        for (int row = 0; row < 4; ++row) {
            if (row == col) continue;
            const double factor = a[row][col];
            for (int j = 0; j < 8; ++j) a[row][j] -= factor * a[col][j];
        }
    }
    Matrix4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = float(a[i][j + 4]);
    return r;
}

std::optional<Transform> Transform::fromMatrix(const Matrix4& matrix) {
    auto inv = matrix.inverse();
    if (!inv) return std::nullopt;
    return Transform(matrix, *inv);
}

Transform Transform::translate(Vec3f d) {
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    m.m[0][3] = d.x;
    m.m[1][3] = d.y;
    m.m[2][3] = d.z;
    inv.m[0][3] = -d.x;
    inv.m[1][3] = -d.y;
    inv.m[2][3] = -d.z;
    return {m, inv};
}

Transform Transform::scale(Vec3f f) {
    Matrix4 m = Matrix4::identity(), inv = Matrix4::identity();
    m.m[0][0] = f.x;
    m.m[1][1] = f.y;
    m.m[2][2] = f.z;
    inv.m[0][0] = 1.0f / f.x;
    inv.m[1][1] = 1.0f / f.y;
    inv.m[2][2] = 1.0f / f.z;
    return {m, inv};
}

Transform Transform::rotate(float angleDegrees, Vec3f axis) {
    const Vec3f a = normalize(axis);
    const double theta = double(angleDegrees) * std::numbers::pi / 180.0;
    const float s = float(std::sin(theta)), c = float(std::cos(theta));
    Matrix4 m = Matrix4::identity();
    m.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
    m.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
    m.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
    m.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
    m.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
    m.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
    m.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
    m.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
    m.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
    return {m, m.transposed()};  // rotations are orthogonal
}

std::optional<Transform> Transform::lookAt(Vec3f from, Vec3f to, Vec3f up) {
    const Vec3f forward = to - from;
    if (!(lengthSquared(forward) > 0.0f) || !(lengthSquared(up) > 0.0f)) return std::nullopt;
    const Vec3f f = normalize(forward);
    const Vec3f rightUnnormalized = cross(f, normalize(up));
    if (!(length(rightUnnormalized) > 1e-6f)) return std::nullopt;
    const Vec3f right = normalize(rightUnnormalized);
    const Vec3f trueUp = cross(right, f);
    Matrix4 m = Matrix4::identity();
    for (int i = 0; i < 3; ++i) {
        m.m[i][0] = right[i];
        m.m[i][1] = trueUp[i];
        m.m[i][2] = f[i];
        m.m[i][3] = from[i];
    }
    return fromMatrix(m);
}

Transform Transform::operator*(const Transform& o) const {
    return {matrix_ * o.matrix_, o.inverse_ * inverse_};
}

Vec3f Transform::applyPoint(Vec3f p) const {
    const auto& m = matrix_.m;
    Vec3f r{m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    const float w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
    return w == 1.0f ? r : r / w;
}

Vec3f Transform::applyVector(Vec3f v) const {
    const auto& m = matrix_.m;
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

Vec3f Transform::applyNormal(Vec3f n) const {
    const auto& mi = inverse_.m;
    return {mi[0][0] * n.x + mi[1][0] * n.y + mi[2][0] * n.z,
            mi[0][1] * n.x + mi[1][1] * n.y + mi[2][1] * n.z,
            mi[0][2] * n.x + mi[1][2] * n.y + mi[2][2] * n.z};
}

bool Transform::swapsHandedness() const {
    const auto& m = matrix_.m;
    const float det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                      m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                      m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return det < 0.0f;
}

}  // namespace penumbra
