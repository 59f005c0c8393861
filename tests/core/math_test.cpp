// Vectors, orthonormal frames and affine transforms against identities and hand-computed values.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/float_error.h"
#include "core/frame.h"
#include "core/motion.h"
#include "core/ray_offset.h"
#include "core/transform.h"
#include "core/trig.h"
#include "core/vec.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::UniformRng;

// Component-wise closeness with an absolute tolerance, reporting both vectors on failure.
::testing::AssertionResult near(Vec3f a, Vec3f b, float tolerance) {
    if (std::abs(a.x - b.x) <= tolerance && std::abs(a.y - b.y) <= tolerance &&
        std::abs(a.z - b.z) <= tolerance)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x
                                         << ", " << b.y << ", " << b.z << "), tolerance " << tolerance;
}

Vec3f randomVector(UniformRng& rng, float scale = 4.0f) {
    return {scale * (2.0f * rng.next() - 1.0f), scale * (2.0f * rng.next() - 1.0f),
            scale * (2.0f * rng.next() - 1.0f)};
}

Vec3f randomUnitVector(UniformRng& rng) {
    for (;;) {  // rejection from the cube keeps the direction uniform
        const Vec3f v = randomVector(rng, 1.0f);
        const float l2 = lengthSquared(v);
        if (l2 > 1e-4f && l2 <= 1.0f) return normalize(v);
    }
}

// ---- vectors ----------------------------------------------------------------------------------

TEST(Vec, CrossOfBasisVectorsIsRightHanded) {
    const Vec3f x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    EXPECT_EQ(cross(x, y), z);
    EXPECT_EQ(cross(y, z), x);
    EXPECT_EQ(cross(z, x), y);
    EXPECT_EQ(cross(y, x), -z);
    EXPECT_EQ(cross(x, x), Vec3f(0, 0, 0));
}

TEST(Vec, CrossAndDotIdentities) {
    UniformRng rng(1);
    for (int i = 0; i < 1000; ++i) {
        const Vec3f a = randomVector(rng), b = randomVector(rng), c = randomVector(rng);
        const Vec3f axb = cross(a, b);
        const float scale = length(a) * length(b);
        // a x b is perpendicular to both factors and anti-commutes.
        EXPECT_NEAR(dot(axb, a), 0.0f, 1e-5f * scale * length(a));
        EXPECT_NEAR(dot(axb, b), 0.0f, 1e-5f * scale * length(b));
        EXPECT_TRUE(near(cross(b, a), -axb, 1e-6f * scale));
        // Lagrange's identity: |a x b|^2 = |a|^2 |b|^2 - (a.b)^2.
        EXPECT_NEAR(lengthSquared(axb), lengthSquared(a) * lengthSquared(b) - dot(a, b) * dot(a, b),
                    1e-4f * scale * scale);
        // Scalar triple product is invariant under cyclic permutation.
        EXPECT_NEAR(dot(a, cross(b, c)), dot(b, cross(c, a)), 1e-4f * scale * length(c));
        EXPECT_EQ(dot(a, b), dot(b, a));
        EXPECT_NEAR(dot(a, a), length(a) * length(a), 1e-5f * dot(a, a));
    }
    EXPECT_EQ(dot(Vec3f(1, 2, 3), Vec3f(4, -5, 6)), 12.0f);
    EXPECT_EQ(cross(Vec3f(1, 2, 3), Vec3f(4, 5, 6)), Vec3f(-3, 6, -3));
    EXPECT_NEAR(length(normalize(Vec3f(3, -4, 12))), 1.0f, 1e-7f);
}

TEST(Vec, FaceForward) {
    EXPECT_EQ(faceForward(Vec3f(0, 0, 1), Vec3f(0, 1, -1)), Vec3f(0, 0, -1));
    EXPECT_EQ(faceForward(Vec3f(0, 0, 1), Vec3f(0, 1, 1)), Vec3f(0, 0, 1));
}

// ---- frames -----------------------------------------------------------------------------------

void expectOrthonormalRightHanded(const Frame& f, Vec3f n) {
    constexpr float eps = 2e-6f;
    EXPECT_EQ(f.n, n);
    EXPECT_NEAR(length(f.s), 1.0f, eps);
    EXPECT_NEAR(length(f.t), 1.0f, eps);
    EXPECT_NEAR(dot(f.s, f.t), 0.0f, eps);
    EXPECT_NEAR(dot(f.s, f.n), 0.0f, eps);
    EXPECT_NEAR(dot(f.t, f.n), 0.0f, eps);
    // Right-handed: s x t = n (so local +z, the normal, is s x t).
    EXPECT_TRUE(near(cross(f.s, f.t), n, 4e-6f));
    EXPECT_TRUE(isFinite(f.s) && isFinite(f.t));
}

TEST(Frame, FromNormalIsOrthonormalAndRightHanded) {
    // The branch points of the construction: exactly +-z, the equator (with z = +0 and -0), and
    // normals just off -z, where a naive construction divides by ~0.
    std::vector<Vec3f> normals = {{0, 0, 1},
                                  {0, 0, -1},
                                  {1, 0, 0},
                                  {-1, 0, 0},
                                  {0, 1, 0},
                                  {0, -1, 0},
                                  {1, 0, -0.0f},
                                  {0, 1, -0.0f},
                                  normalize(Vec3f(1e-4f, -2e-4f, -1)),
                                  normalize(Vec3f(-3e-7f, 1e-7f, -1)),
                                  normalize(Vec3f(1e-4f, 1e-4f, 1))};
    UniformRng rng(2);
    for (int i = 0; i < 20000; ++i) normals.push_back(randomUnitVector(rng));
    for (Vec3f n : normals) {
        SCOPED_TRACE(::testing::Message() << "n = (" << n.x << ", " << n.y << ", " << n.z << ")");
        expectOrthonormalRightHanded(Frame::fromNormal(n), n);
        if (::testing::Test::HasFailure()) break;  // one report is enough
    }
}

TEST(Frame, LocalWorldRoundTrip) {
    UniformRng rng(3);
    for (int i = 0; i < 2000; ++i) {
        const Vec3f n = randomUnitVector(rng);
        const Frame f = Frame::fromNormal(n);
        EXPECT_TRUE(near(f.toLocal(n), Vec3f(0, 0, 1), 2e-6f));
        EXPECT_TRUE(near(f.toWorld(Vec3f(0, 0, 1)), n, 1e-7f));
        const Vec3f v = randomVector(rng);
        EXPECT_TRUE(near(f.toWorld(f.toLocal(v)), v, 1e-5f));
        EXPECT_TRUE(near(f.toLocal(f.toWorld(v)), v, 1e-5f));
        // A rotation keeps lengths and the sign of the cosine with the normal.
        EXPECT_NEAR(length(f.toLocal(v)), length(v), 1e-5f);
        EXPECT_NEAR(f.toLocal(v).z, dot(v, n), 1e-5f);
    }
}

// FrameLanes converts as Frame does, bit for bit: the integrator uses it in Frame's place and its
// images must not change. Vectors of mixed scales and signs, with zeros, so that rounding differs
// whenever the order of the products or the sums does.
TEST(Frame, LanesConvertBitForBitAsTheFrame) {
    UniformRng rng(4);
    for (int i = 0; i < 20000; ++i) {
        const Frame f = Frame::fromNormal(randomUnitVector(rng));
        const FrameLanes lanes(f);
        Vec3f v = randomVector(rng) * std::exp2(float(i % 40) - 20.0f);
        if (i % 7 == 0) v.y = 0.0f;
        const Vec3f local = f.toLocal(v), world = f.toWorld(v);
        const Vec3f laneLocal = lanes.toLocal(v), laneWorld = lanes.toWorld(v);
        using Bits = std::array<uint32_t, 3>;
        ASSERT_EQ(std::bit_cast<Bits>(laneLocal), std::bit_cast<Bits>(local)) << i;
        ASSERT_EQ(std::bit_cast<Bits>(laneWorld), std::bit_cast<Bits>(world)) << i;
    }
}

// ---- transforms -------------------------------------------------------------------------------

TEST(Transform, TranslateMovesPointsButNotVectorsOrNormals) {
    const Transform t = Transform::translate({1, -2, 3});
    EXPECT_EQ(t.applyPoint({4, 5, 6}), Vec3f(5, 3, 9));
    EXPECT_EQ(t.applyVector({4, 5, 6}), Vec3f(4, 5, 6));
    EXPECT_EQ(t.applyNormal({0, 0, 1}), Vec3f(0, 0, 1));
    EXPECT_EQ(t.inverse().applyPoint({5, 3, 9}), Vec3f(4, 5, 6));
}

TEST(Transform, Scale) {
    const Transform s = Transform::scale({2, 3, -4});
    EXPECT_EQ(s.applyPoint({1, 1, 1}), Vec3f(2, 3, -4));
    EXPECT_EQ(s.applyVector({0.5f, -1, 0.25f}), Vec3f(1, -3, -1));
    EXPECT_EQ(s.inverse().applyPoint({2, 3, -4}), Vec3f(1, 1, 1));
    // Normals scale by the inverse: the normal of the plane x = const stays along x, shrunk.
    EXPECT_TRUE(near(s.applyNormal({1, 0, 0}), Vec3f(0.5f, 0, 0), 1e-7f));
}

TEST(Transform, RotateIsRightHandedAboutTheAxis) {
    constexpr float eps = 1e-6f;
    EXPECT_TRUE(near(Transform::rotate(90, {0, 0, 1}).applyVector({1, 0, 0}), Vec3f(0, 1, 0), eps));
    EXPECT_TRUE(near(Transform::rotate(90, {0, 0, 1}).applyVector({0, 1, 0}), Vec3f(-1, 0, 0), eps));
    EXPECT_TRUE(near(Transform::rotate(90, {1, 0, 0}).applyVector({0, 1, 0}), Vec3f(0, 0, 1), eps));
    EXPECT_TRUE(near(Transform::rotate(90, {0, 1, 0}).applyVector({0, 0, 1}), Vec3f(1, 0, 0), eps));
    // The axis need not be unit length.
    EXPECT_TRUE(near(Transform::rotate(90, {0, 0, 7}).applyVector({1, 0, 0}), Vec3f(0, 1, 0), eps));
    // 30 degrees about z: (cos 30, sin 30, 0).
    EXPECT_TRUE(near(Transform::rotate(30, {0, 0, 1}).applyPoint({1, 0, 0}),
                     Vec3f(std::sqrt(3.0f) / 2.0f, 0.5f, 0), eps));
    // 120 degrees about (1,1,1) cycles the axes x -> y -> z -> x.
    const Transform r = Transform::rotate(120, {1, 1, 1});
    EXPECT_TRUE(near(r.applyVector({1, 0, 0}), Vec3f(0, 1, 0), eps));
    EXPECT_TRUE(near(r.applyVector({0, 1, 0}), Vec3f(0, 0, 1), eps));
    EXPECT_TRUE(near(r.applyVector({0, 0, 1}), Vec3f(1, 0, 0), eps));
    // Points on the axis stay put, and the inverse rotates back.
    EXPECT_TRUE(near(r.applyPoint({2, 2, 2}), Vec3f(2, 2, 2), 4 * eps));
    EXPECT_TRUE(near(r.inverse().applyVector({0, 1, 0}), Vec3f(1, 0, 0), eps));
}

TEST(Transform, CompositionAppliesTheRightOperandFirst) {
    const Transform t = Transform::translate({1, 2, 3});
    const Transform s = Transform::scale({2, 2, 2});
    const Vec3f p{1, 1, 1};
    EXPECT_EQ((t * s).applyPoint(p), Vec3f(3, 4, 5));  // scale, then translate
    EXPECT_EQ((s * t).applyPoint(p), Vec3f(4, 6, 8));  // translate, then scale
    const Transform r = Transform::rotate(90, {0, 0, 1});
    EXPECT_TRUE(near((t * r).applyPoint({1, 0, 0}), Vec3f(1, 3, 3), 1e-6f));
    EXPECT_TRUE(near((r * t).applyPoint({1, 0, 0}), Vec3f(-2, 2, 3), 1e-6f));
}

Transform randomTransform(UniformRng& rng) {
    const Vec3f factors{0.2f + 3 * rng.next(), 0.2f + 3 * rng.next(), 0.2f + 3 * rng.next()};
    return Transform::translate(randomVector(rng)) *
           Transform::rotate(360 * rng.next(), randomUnitVector(rng)) * Transform::scale(factors);
}

TEST(Transform, InverseRoundTripsPointsVectorsAndMatrices) {
    UniformRng rng(4);
    for (int i = 0; i < 500; ++i) {
        const Transform a = randomTransform(rng), b = randomTransform(rng);
        const Vec3f p = randomVector(rng);
        EXPECT_TRUE(near(a.inverse().applyPoint(a.applyPoint(p)), p, 1e-4f));
        EXPECT_TRUE(near(a.applyPoint(a.inverse().applyPoint(p)), p, 1e-4f));
        EXPECT_TRUE(near(a.inverse().applyVector(a.applyVector(p)), p, 1e-4f));
        // The composite keeps its inverse in the opposite order: (ab)^-1 = b^-1 a^-1.
        EXPECT_TRUE(near((a * b).inverse().applyPoint((a * b).applyPoint(p)), p, 2e-4f));
        EXPECT_TRUE(
            near((a * b).inverse().applyPoint(p), b.inverse().applyPoint(a.inverse().applyPoint(p)), 1e-4f));
        // The stored inverse agrees with the Gauss-Jordan inverse of the matrix.
        const auto inv = a.matrix().inverse();
        ASSERT_TRUE(inv.has_value());
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(inv->m[r][c], a.inverseMatrix().m[r][c], 1e-4f);
        const Matrix4 product = a.matrix() * *inv;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(product.m[r][c], r == c ? 1.0f : 0.0f, 1e-5f);
    }
}

TEST(Transform, FromMatrixComputesTheInverse) {
    Matrix4 m = Matrix4::identity();
    m.m[0][1] = 2;   // shear
    m.m[2][3] = -5;  // translation
    const auto t = Transform::fromMatrix(m);
    ASSERT_TRUE(t.has_value());
    EXPECT_EQ(t->applyPoint({1, 1, 1}), Vec3f(3, 1, -4));
    EXPECT_TRUE(near(t->inverse().applyPoint({3, 1, -4}), Vec3f(1, 1, 1), 1e-6f));
}

TEST(Transform, SingularMatricesHaveNoInverse) {
    Matrix4 zeroRow = Matrix4::identity();
    zeroRow.m[1][1] = 0;
    EXPECT_FALSE(zeroRow.inverse().has_value());
    EXPECT_FALSE(Transform::fromMatrix(zeroRow).has_value());

    // Rows (1,2,3), (4,5,6), (7,8,9) are linearly dependent.
    Matrix4 dependent = Matrix4::identity();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) dependent.m[r][c] = float(3 * r + c + 1);
    EXPECT_FALSE(dependent.inverse().has_value());

    EXPECT_FALSE(Matrix4{}.inverse().has_value());  // all zeros

    Matrix4 notFinite = Matrix4::identity();
    notFinite.m[0][3] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(notFinite.inverse().has_value());
    notFinite.m[0][3] = std::numeric_limits<float>::infinity();
    EXPECT_FALSE(notFinite.inverse().has_value());

    // Small but regular scales are still invertible.
    EXPECT_TRUE(Transform::scale({1e-3f, 1e-3f, 1e-3f}).matrix().inverse().has_value());
}

TEST(Transform, NormalsStayPerpendicularUnderNonUniformScale) {
    UniformRng rng(5);
    const Transform t = Transform::rotate(37, {1, 2, 3}) * Transform::scale({1, 4, 0.25f}) *
                        Transform::rotate(-70, {0, 1, 1}) * Transform::translate({1, 2, 3});
    for (int i = 0; i < 1000; ++i) {
        const Vec3f t1 = randomUnitVector(rng), t2 = randomUnitVector(rng);
        const Vec3f n = cross(t1, t2);
        if (length(n) < 0.1f) continue;
        const Vec3f nw = normalize(t.applyNormal(n));
        EXPECT_NEAR(dot(nw, normalize(t.applyVector(t1))), 0.0f, 1e-5f);
        EXPECT_NEAR(dot(nw, normalize(t.applyVector(t2))), 0.0f, 1e-5f);
    }
    // Transforming the normal like a vector would be wrong here: it is not perpendicular then,
    // which is what makes this test able to fail.
    const Transform s = Transform::scale({1, 4, 1});
    const Vec3f tangent{1, 1, 0}, normal{1, -1, 0};
    EXPECT_GT(std::abs(dot(normalize(s.applyVector(normal)), normalize(s.applyVector(tangent)))), 0.5f);
    EXPECT_NEAR(dot(s.applyNormal(normal), s.applyVector(tangent)), 0.0f, 1e-6f);
}

TEST(Transform, LookAtMapsCameraAxes) {
    // Looking down -z with +y up: the camera's +x (image right) is world +x.
    const auto simple = Transform::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    ASSERT_TRUE(simple.has_value());
    EXPECT_TRUE(near(simple->applyVector({0, 0, 1}), Vec3f(0, 0, -1), 1e-6f));
    EXPECT_TRUE(near(simple->applyVector({0, 1, 0}), Vec3f(0, 1, 0), 1e-6f));
    EXPECT_TRUE(near(simple->applyVector({1, 0, 0}), Vec3f(1, 0, 0), 1e-6f));

    const Vec3f from{1, 2, 3}, to{-2, 6, 3.5f}, up{0.3f, 0.2f, 1};
    const auto cam = Transform::lookAt(from, to, up);
    ASSERT_TRUE(cam.has_value());
    const Vec3f forward = normalize(to - from);
    EXPECT_TRUE(near(cam->applyPoint({0, 0, 0}), from, 1e-6f));
    EXPECT_TRUE(near(cam->applyVector({0, 0, 1}), forward, 1e-6f));
    EXPECT_TRUE(near(cam->applyPoint({0, 0, length(to - from)}), to, 1e-5f));
    const Vec3f camUp = cam->applyVector({0, 1, 0}), camRight = cam->applyVector({1, 0, 0});
    EXPECT_NEAR(dot(camUp, forward), 0.0f, 1e-6f);
    EXPECT_GT(dot(camUp, up), 0.0f);  // up stays on the side of the requested up
    EXPECT_NEAR(length(camUp), 1.0f, 1e-6f);
    // Right of the image for a viewer looking along `forward` with `up` up: forward x up.
    EXPECT_TRUE(near(camRight, normalize(cross(forward, up)), 1e-6f));
    // x right, y up, z forward is a left-handed frame, so the camera-to-world map flips it.
    EXPECT_TRUE(cam->swapsHandedness());
    EXPECT_TRUE(near(cam->inverse().applyPoint(to), Vec3f(0, 0, length(to - from)), 1e-5f));
}

TEST(Transform, LookAtRejectsDegenerateInput) {
    EXPECT_FALSE(Transform::lookAt({1, 1, 1}, {1, 1, 1}, {0, 1, 0}).has_value());  // no direction
    EXPECT_FALSE(Transform::lookAt({0, 0, 0}, {0, 5, 0}, {0, 2, 0}).has_value());  // up parallel
    EXPECT_FALSE(Transform::lookAt({0, 0, 0}, {0, 0, 1}, {0, 0, 0}).has_value());  // no up
}

TEST(Transform, SwapsHandedness) {
    EXPECT_FALSE(Transform().swapsHandedness());
    EXPECT_FALSE(Transform::rotate(123, {1, 2, 3}).swapsHandedness());
    EXPECT_FALSE(Transform::translate({-1, -1, -1}).swapsHandedness());
    EXPECT_TRUE(Transform::scale({-1, 1, 1}).swapsHandedness());
    EXPECT_FALSE(Transform::scale({-1, -1, 1}).swapsHandedness());
    EXPECT_TRUE(Transform::scale({-2, -3, -0.5f}).swapsHandedness());
    EXPECT_TRUE(
        (Transform::rotate(40, {0, 1, 0}) * Transform::scale({1, 1, -1}) * Transform::translate({3, 0, 0}))
            .swapsHandedness());
}

// The polynomials against double-precision libm over their whole range, 2^20 + 1 angles: within
// 2 ulps of 1 (1.2e-7) absolutely; the sine also relatively near 0, where its value is tiny.
// TransformKey::toTransform writes the product translate * rotation * scale out entry by entry;
// it must give the general product's bits, matrix and inverse (renders with motion depend on them).
TEST(Transform, AKeysTransformIsItsFactorsProductBitForBit) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> coordinate(-50.0f, 50.0f), factor(0.01f, 20.0f), unit(-1.0f, 1.0f);
    for (int i = 0; i < 20000; ++i) {
        TransformKey key;
        key.translation = {coordinate(rng), coordinate(rng), i % 7 == 0 ? -0.0f : coordinate(rng)};
        key.scale = {factor(rng), i % 3 == 0 ? -factor(rng) : factor(rng), factor(rng)};
        // Axis-aligned rotations too: their matrices hold zeros of either sign.
        const Vec3f axis =
            i % 5 == 0 ? Vec3f{0.0f, 1.0f, 0.0f} : Vec3f{unit(rng), unit(rng), unit(rng) + 2.0f};
        key.rotation =
            Quaternion::fromAxisAngle(axis, i % 5 == 0 ? 90.0f * float(i % 4) : 180.0f * unit(rng));
        const Matrix4 r = key.rotation.toMatrix();
        const Transform product = Transform::translate(key.translation) * Transform(r, r.transposed()) *
                                  Transform::scale(key.scale);
        const Transform written = key.toTransform();
        for (int row = 0; row < 4; ++row) {
            for (int column = 0; column < 4; ++column) {
                ASSERT_EQ(std::bit_cast<uint32_t>(written.matrix().m[row][column]),
                          std::bit_cast<uint32_t>(product.matrix().m[row][column]))
                    << "key " << i << " matrix " << row << "," << column;
                ASSERT_EQ(std::bit_cast<uint32_t>(written.inverseMatrix().m[row][column]),
                          std::bit_cast<uint32_t>(product.inverseMatrix().m[row][column]))
                    << "key " << i << " inverse " << row << "," << column;
            }
        }
    }
}

TEST(Trig, CosSinQuarterPiMatchesLibmWithinTwoUlps) {
    const int n = 1 << 20;
    double worstCos = 0, worstSinRelative = 0;
    for (int i = 0; i <= n; ++i) {
        const float a = float(-M_PI / 4 + (M_PI / 2) * i / n);
        const Vec2f cs = cosSinQuarterPi(a);
        worstCos = std::max(worstCos, std::abs(double(cs.x) - std::cos(double(a))));
        if (a != 0.0f)
            worstSinRelative = std::max(worstSinRelative, std::abs(double(cs.y) / std::sin(double(a)) - 1.0));
        else
            EXPECT_EQ(cs.y, 0.0f);
    }
    EXPECT_LE(worstCos, 0x1p-23);
    EXPECT_LE(worstSinRelative, 0x1p-22);
}

// A whole turn (the azimuths of the sphere, cone and lobe warps): within 4 ulps of 1 against
// double-precision libm at 2^20 + 1 values of u in [0, 1], the quarter turns exact.
TEST(Trig, CosSinTurnMatchesLibmOverAWholeTurn) {
    const int n = 1 << 20;
    double worst = 0;
    for (int i = 0; i <= n; ++i) {
        const float u = float(double(i) / n);
        const Vec2f cs = cosSinTurn(u);
        const double angle = 2.0 * M_PI * double(u);
        worst = std::max(
            {worst, std::abs(double(cs.x) - std::cos(angle)), std::abs(double(cs.y) - std::sin(angle))});
    }
    EXPECT_LE(worst, 0x1p-22);
    for (const float u : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
        const Vec2f cs = cosSinTurn(u);
        EXPECT_EQ(cs.x, float(std::lround(std::cos(2.0 * M_PI * u)))) << u;
        EXPECT_EQ(cs.y, float(std::lround(std::sin(2.0 * M_PI * u)))) << u;
    }
}

// The moved point lies beyond the plane through every point of the error box: in exact arithmetic
// (double holds these sums exactly enough), dot(moved - p, n) >= dot(|n|, pointError), at every
// magnitude, with zero errors (then moved differs from p only where n is non-zero) and zero points.
TEST(RayOffset, ClearsTheErrorBoxAlongTheNormal) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), exponent(-40.0f, 40.0f);
    int checked = 0;
    for (int i = 0; i < 100000; ++i) {
        Vec3f p, e, n{unit(rng), unit(rng), unit(rng)};
        if (lengthSquared(n) == 0.0f) continue;
        n = normalize(n);
        const float magnitude = std::exp2(exponent(rng));
        for (int a = 0; a < 3; ++a) {
            p[a] = i % 10 == 0 ? 0.0f : unit(rng) * magnitude;
            e[a] = i % 7 == 0 ? 0.0f : std::abs(unit(rng)) * magnitude * 1e-6f;
        }
        const Vec3f q = offsetRayOrigin(p, e, n);
        double along = 0, bound = 0;
        for (int a = 0; a < 3; ++a) {
            along += (double(q[a]) - double(p[a])) * double(n[a]);
            bound += std::abs(double(n[a])) * double(e[a]);
            if (n[a] > 0.0f) {
                ASSERT_GT(q[a], p[a]);
            }
            if (n[a] < 0.0f) {
                ASSERT_LT(q[a], p[a]);
            }
        }
        ASSERT_GE(along, bound) << "p.x " << p.x << " e.x " << e.x << " n.x " << n.x;
        ++checked;
    }
    EXPECT_GT(checked, 99000);
}

// A point on a plane at coordinate 0 with exact vertices has no error along its normal: it still
// moves by kMinimumRelativeOffset of its largest coordinate, to a normal float (not to 1.2e-38, on
// which Embree runs slowly), and by no more than that and a float's step: rounding the floor and
// the sum costs at most half a float step (2^-24 relative), the extra step one (2^-23), so 2^-20
// bounds both with room.
TEST(RayOffset, AnExactPointMovesByTheMinimumRelativeOffset) {
    for (const Vec3f p : {Vec3f{300.0f, 0.0f, 200.0f}, Vec3f{-1e-6f, 0.0f, 3e-6f}, Vec3f{0.0f, 0.0f, 5e7f}}) {
        for (const float sign : {1.0f, -1.0f}) {
            const Vec3f n{0.0f, sign, 0.0f};
            const Vec3f q = offsetRayOrigin(p, Vec3f{0.0f, 0.0f, 0.0f}, n);
            const float floor = maxComponent(abs(p)) * kMinimumRelativeOffset;
            EXPECT_EQ(q.x, p.x);
            EXPECT_EQ(q.z, p.z);
            EXPECT_EQ(std::fpclassify(q.y), FP_NORMAL) << q.y;
            EXPECT_GE(q.y * sign, floor) << "p " << p.x << " " << p.y << " " << p.z;
            EXPECT_LE(q.y * sign, floor * (1.0f + 0x1p-20f)) << "p " << p.x << " " << p.y << " " << p.z;
        }
    }
}

TEST(FloatError, NextFloatStepsOneValue) {
    EXPECT_EQ(nextFloatUp(1.0f), std::nextafter(1.0f, 2.0f));
    EXPECT_EQ(nextFloatDown(1.0f), std::nextafter(1.0f, 0.0f));
    EXPECT_EQ(nextFloatUp(-1.0f), std::nextafter(-1.0f, 0.0f));
    EXPECT_EQ(nextFloatUp(0.0f), std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(nextFloatUp(-0.0f), std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(nextFloatDown(0.0f), -std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(nextFloatUp(std::numeric_limits<float>::infinity()), std::numeric_limits<float>::infinity());
    EXPECT_GT(gamma(3), 3.0f * 0x1p-24f);
}

}  // namespace
}  // namespace penumbra
