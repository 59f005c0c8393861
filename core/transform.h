// Affine transforms as 4x4 matrices that keep their inverse, for placing meshes and cameras.
#pragma once

#include <array>
#include <optional>

#include "core/vec.h"

namespace penumbra {

struct Matrix4 {
    std::array<std::array<float, 4>, 4> m{};  // row-major: m[row][column]

    static Matrix4 identity();
    Matrix4 operator*(const Matrix4& o) const;
    Matrix4 transposed() const;
    // Empty when the matrix is singular (or not finite).
    std::optional<Matrix4> inverse() const;
    bool operator==(const Matrix4& o) const { return m == o.m; }
};

class Transform {
public:
    Transform() : matrix_(Matrix4::identity()), inverse_(Matrix4::identity()) {}
    Transform(const Matrix4& matrix, const Matrix4& inverse) : matrix_(matrix), inverse_(inverse) {}
    // Empty when the matrix cannot be inverted.
    static std::optional<Transform> fromMatrix(const Matrix4& matrix);

    static Transform translate(Vec3f delta);
    static Transform scale(Vec3f factors);                    // factors must be non-zero
    static Transform rotate(float angleDegrees, Vec3f axis);  // right-handed, axis need not be unit
    // Camera-to-world transform of a camera at `from` looking at `to`; camera space has +z forward,
    // +y up and +x to the right of the image. Empty when the directions are degenerate.
    static std::optional<Transform> lookAt(Vec3f from, Vec3f to, Vec3f up);

    // `a * b` applies b first, then a.
    Transform operator*(const Transform& o) const;
    Transform inverse() const { return {inverse_, matrix_}; }

    Vec3f applyPoint(Vec3f p) const;
    Vec3f applyVector(Vec3f v) const;
    // Normals transform with the inverse transpose; the result is not normalized.
    Vec3f applyNormal(Vec3f n) const;
    // True when the transform flips handedness (negative determinant), which flips winding.
    bool swapsHandedness() const;

    const Matrix4& matrix() const { return matrix_; }
    const Matrix4& inverseMatrix() const { return inverse_; }

private:
    Matrix4 matrix_;
    Matrix4 inverse_;
};

}  // namespace penumbra
