// The 4-wide watertight triangle test (accel/bvh_triangle4.h) against the scalar one
// (geometry/triangle.h): every lane must give the scalar test's answer bit for bit, on random
// triangles, on rays through their edges and vertices (where edge functions round to zero and the
// scalar test recomputes them in double: those lanes must be reported for the scalar test), on
// degenerate triangles, and on rays along axes (zero direction components).
#include "accel/bvh_triangle4.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/hash.h"

namespace penumbra {
namespace {

float uniform(uint64_t test, uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(test, index, dimension) >> 32));
}

Vec3f randomPoint(uint64_t test, uint64_t index, uint64_t dimension, float scale) {
    return Vec3f{uniform(test, index, dimension) - 0.5f, uniform(test, index, dimension + 1) - 0.5f,
                 uniform(test, index, dimension + 2) - 0.5f} *
           scale;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

struct Counts {
    int hits = 0, fallbacks = 0;
};

// Tests four triangles both ways, and expects the same answers.
void expectSameAsScalar(Vec3f origin, Vec3f direction, const Vec3f (&triangles)[4][3], float tMin, float tMax,
                        Counts& counts) {
    alignas(16) TriangleLanes lanes;
    float vertices[4][9];
    for (int lane = 0; lane < 4; ++lane)
        for (int v = 0; v < 3; ++v)
            for (int axis = 0; axis < 3; ++axis) {
                lanes[3 * v + axis][lane] = triangles[lane][v][axis];
                vertices[lane][3 * v + axis] = triangles[lane][v][axis];
            }
    const WatertightRay ray(origin, direction);
    TriangleHits4 hits;
    intersectTrianglesWatertight4(WatertightRay4(ray), lanes, tMin, tMax, hits);
    for (int lane = 0; lane < 4; ++lane) {
        TriangleHit scalar;
        const bool scalarHit = intersectTriangleWatertight(ray, vertices[lane], tMin, tMax, scalar);
        if (hits.fallback & (1 << lane)) {
            ++counts.fallbacks;
            EXPECT_FALSE(hits.hit & (1 << lane)) << "a lane for the scalar test is not reported as a hit";
            continue;
        }
        ASSERT_EQ(bool(hits.hit & (1 << lane)), scalarHit) << "lane " << lane;
        if (!scalarHit) continue;
        ++counts.hits;
        EXPECT_TRUE(sameBits(hits.t[lane], scalar.t)) << hits.t[lane] << " vs " << scalar.t;
        EXPECT_TRUE(sameBits(hits.b1[lane], scalar.b1));
        EXPECT_TRUE(sameBits(hits.b2[lane], scalar.b2));
    }
}

TEST(Triangle4, RandomTrianglesAndRaysAgreeBitForBit) {
    Counts counts;
    for (uint64_t i = 0; i < 20000; ++i) {
        Vec3f triangles[4][3];
        for (int lane = 0; lane < 4; ++lane)
            for (int v = 0; v < 3; ++v) triangles[lane][v] = randomPoint(1, 4 * i + lane, 3 * v, 2.0f);
        const Vec3f origin = randomPoint(2, i, 0, 4.0f);
        // Aimed at a point of lane 0's triangle, so a good share of the tests hit.
        const float a = uniform(3, i, 0), b = uniform(3, i, 1) * (1.0f - a);
        const Vec3f target = triangles[0][0] * (1.0f - a - b) + triangles[0][1] * a + triangles[0][2] * b;
        expectSameAsScalar(origin, target - origin, triangles, 0.0f, std::numeric_limits<float>::infinity(),
                           counts);
        expectSameAsScalar(origin, target - origin, triangles, 0.5f, 1.0f, counts);  // a bounded interval
    }
    EXPECT_GT(counts.hits, 20000);
}

// Rays through shared edges and vertices of a fan and along axes: edge functions of exactly zero.
TEST(Triangle4, EdgesVerticesAndAxisRaysAgreeBitForBit) {
    Counts counts;
    for (uint64_t i = 0; i < 20000; ++i) {
        // Small integer coordinates make exact zeros common.
        auto grid = [&](uint64_t d) { return std::floor(uniform(4, i, d) * 5.0f) - 2.0f; };
        const Vec3f c{grid(0), grid(1), 0.0f};
        const Vec3f triangles[4][3] = {{c, c + Vec3f{1, 0, 0}, c + Vec3f{0, 1, 0}},
                                       {c, c + Vec3f{0, 1, 0}, c + Vec3f{-1, 0, 0}},
                                       {c + Vec3f{1, 0, 0}, c + Vec3f{0, 1, 0}, c + Vec3f{1, 1, 0}},
                                       {c, c + Vec3f{1, 0, 0}, c + Vec3f{2, 0, 0}}};  // degenerate
        const Vec3f target = c + Vec3f{std::floor(uniform(5, i, 0) * 3.0f) * 0.5f,
                                       std::floor(uniform(5, i, 1) * 3.0f) * 0.5f, 0.0f};
        const Vec3f origin = i % 2 ? target + Vec3f{0, 0, 3} : Vec3f{grid(2), grid(3), grid(4) + 0.5f};
        if (origin.x == target.x && origin.y == target.y && origin.z == target.z) continue;
        expectSameAsScalar(origin, target - origin, triangles, 0.0f, std::numeric_limits<float>::infinity(),
                           counts);
    }
    EXPECT_GT(counts.hits, 500);
    EXPECT_GT(counts.fallbacks, 1000) << "the double-precision path was exercised";
}

}  // namespace
}  // namespace penumbra
