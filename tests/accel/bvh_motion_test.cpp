// Motion blur in our BVH (accel/bvh_accelerator.h) against Embree: a mesh that translates,
// rotates and scales, a deforming mesh, a mesh that does both, and moving spheres, beside still
// geometry, on random rays at random shutter times.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "core/hash.h"
#include "core/sampling.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float uniform(uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(0xb0b0, index, dimension) >> 32));
}

// An n x n grid over [-1, 1]^2 in the xy plane, lifted in z by `height`.
template <typename Height>
TriangleMesh makeGrid(int n, Height height) {
    TriangleMesh mesh;
    mesh.name = "grid";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -1.0f + 2.0f * float(i) / float(n), y = -1.0f + 2.0f * float(j) / float(n);
            mesh.positions.push_back({x, y, height(x, y)});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    return mesh;
}

// A closed box [-1, 1]^3 with each face split into n x n quads.
TriangleMesh makeBox(int n) {
    TriangleMesh box;
    box.name = "box";
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {-1.0f, 1.0f}) {
            const TriangleMesh face = makeGrid(n, [&](float, float) { return side; });
            const uint32_t base = uint32_t(box.positions.size());
            for (Vec3f p : face.positions) {
                Vec3f q;
                q[axis] = p.z;
                q[(axis + 1) % 3] = p.x;
                q[(axis + 2) % 3] = p.y;
                box.positions.push_back(q);
            }
            for (uint32_t index : face.indices) box.indices.push_back(base + index);
        }
    return box;
}

TransformKey key(Vec3f scale, Vec3f axis, float degrees, Vec3f translation) {
    TransformKey k;
    k.scale = scale;
    k.rotation = Quaternion::fromAxisAngle(axis, degrees);
    k.translation = translation;
    return k;
}

Sphere makeSphere(Vec3f center, float radius) {
    Sphere s;
    s.name = "sphere";
    s.center = center;
    s.radius = radius;
    return s;
}

Scene makeMovingScene() {
    Scene scene;
    scene.materials = {testing::makeLambert(Rgb(0.5f))};
    // Still: a floor and a sphere.
    scene.meshes.push_back(testing::makeQuad({-6, -3, -6}, {0, 0, 12}, {12, 0, 0}, 0));
    scene.spheres.push_back(makeSphere({3, -2, 3}, 0.7f));
    // 1: a box that moves, turns (by more than 180 degrees over three keys) and stretches.
    TriangleMesh box = makeBox(6);
    box.motion.keys = {key({1, 1, 1}, {0, 1, 0}, 0.0f, {-2, 0, 0}),
                       key({1.5f, 0.8f, 1}, {0.3f, 1, 0.2f}, 110.0f, {0, 1, 0}),
                       key({0.7f, 0.7f, 1.2f}, {0, 1, 0.5f}, 230.0f, {2, 0.5f, -1})};
    scene.meshes.push_back(box);
    // 2: a deforming grid: a wave whose height changes sign between keys.
    TriangleMesh wave = makeGrid(24, [](float, float) { return 0.0f; });
    for (float amplitude : {0.0f, 0.8f, -0.6f, 0.3f}) {
        std::vector<Vec3f> key = wave.positions;
        for (Vec3f& p : key)
            p = {p.x * 2.0f, p.z + amplitude * std::sin(3.0f * p.x) * std::cos(2.0f * p.y) - 1.5f,
                 p.y * 2.0f + amplitude};
        wave.positionKeys.push_back(key);
    }
    wave.positions = wave.positionKeys.front();
    scene.meshes.push_back(wave);
    // 3: a mesh that deforms and moves.
    TriangleMesh both = makeGrid(8, [](float x, float y) { return 0.2f * x * y; });
    both.positionKeys = {both.positions, both.positions};
    for (Vec3f& p : both.positionKeys[1]) p.z += 0.5f * p.x;
    both.motion.keys = {key({0.5f, 0.5f, 0.5f}, {1, 0, 0}, -30.0f, {0, 2, 2}),
                        key({0.6f, 0.5f, 0.4f}, {1, 0, 0}, 60.0f, {1, 2, 1})};
    scene.meshes.push_back(both);
    // Moving spheres: one translating, one scaled non-uniformly (an ellipsoid) and turning.
    Sphere moving = makeSphere({0, 0, 0}, 0.6f);
    moving.motion.keys = {key({1, 1, 1}, {0, 1, 0}, 0.0f, {-3, 1, 2}),
                          key({1, 1, 1}, {0, 1, 0}, 0.0f, {0, -1, 2}),
                          key({1, 1, 1}, {0, 1, 0}, 0.0f, {3, 1, 2})};
    scene.spheres.push_back(moving);
    Sphere ellipsoid = makeSphere({0.5f, 0, 0}, 0.5f);
    ellipsoid.motion.keys = {key({2, 0.5f, 1}, {0, 0, 1}, 0.0f, {0, 0, -3}),
                             key({1, 1.5f, 0.5f}, {0, 0, 1}, 170.0f, {0, 1, -3})};
    scene.spheres.push_back(ellipsoid);
    return scene;
}

TEST(BvhMotion, AgreesWithEmbreeOnRandomRaysAtRandomTimes) {
    const Scene scene = makeMovingScene();
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    constexpr int kRays = 100'000;
    int hits = 0, movingHits = 0, hitMiss = 0, primitive = 0, distance = 0, occlusion = 0;
    for (int i = 0; i < kRays; ++i) {
        Ray ray;
        ray.origin = {-7.0f + 14.0f * uniform(i, 0), -3.0f + 8.0f * uniform(i, 1),
                      -7.0f + 14.0f * uniform(i, 2)};
        const Vec3f target{-3.5f + 7.0f * uniform(i, 3), -2.5f + 5.0f * uniform(i, 4),
                           -4.0f + 7.0f * uniform(i, 5)};
        ray.direction = target - ray.origin;
        ray.tnear = 0.0f;
        ray.tfar = kInf;
        ray.time = uniform(i, 6);
        Hit a, b;
        const bool hitA = embree.intersect(ray, a), hitB = bvh.intersect(ray, b);
        if (embree.occluded(ray) != bvh.occluded(ray)) ++occlusion;
        if (hitA != hitB) {
            ++hitMiss;
            continue;
        }
        if (!hitA) continue;
        ++hits;
        if (a.geomId >= 1) ++movingHits;
        if (a.geomId != b.geomId || a.primId != b.primId) {
            ++primitive;
            continue;
        }
        if (std::abs(a.t - b.t) > 1e-3f * a.t) ++distance;
    }
    const int disagreements = hitMiss + primitive + distance;
    std::printf(
        "moving scene, %d rays at random times: %d hits (%d on moving shapes); %d hit/miss, %d primitive, %d "
        "distance disagreements (agreement %.4f%%); %d occlusion disagreements\n",
        kRays, hits, movingHits, hitMiss, primitive, distance, 100.0 * (1.0 - double(disagreements) / kRays),
        occlusion);
    EXPECT_GT(hits, kRays / 3);
    EXPECT_GT(movingHits, kRays / 10);
    // Embree interpolates its instance transforms and vertices with its own roundings, so rays
    // grazing a silhouette or crossing a shared edge may be answered differently: allowed, rarely.
    EXPECT_LT(disagreements, kRays / 1000);
    EXPECT_LT(occlusion, kRays / 1000);
}

// Hits on moving shapes report the scene's ids: spheres share geomId == meshes.size() with the
// sphere index as primId, meshes their own index.
TEST(BvhMotion, MovingShapesReportTheScenesIds) {
    const Scene scene = makeMovingScene();
    const BvhAccelerator bvh(scene);
    Ray ray;
    ray.direction = {0, 0, -1};
    ray.tfar = kInf;
    // The translating sphere is at (0, -1, 2) at the middle of the shutter.
    ray.origin = {0, -1, 10};
    ray.time = 0.5f;
    Hit hit;
    ASSERT_TRUE(bvh.intersect(ray, hit));
    EXPECT_EQ(hit.geomId, scene.meshes.size());
    EXPECT_EQ(hit.primId, 1u);
    EXPECT_NEAR(hit.t, 10.0f - 2.0f - 0.6f, 1e-4f);
    // At the shutter's opening it is at (-3, 1, 2): the ray passes where it will be.
    ray.time = 0.0f;
    EXPECT_FALSE(bvh.intersect(ray, hit) && hit.geomId == scene.meshes.size() && hit.primId == 1u);
    // The box starts at (-2, 0, 0), unrotated: its +z face at z = 1.
    ray.origin = {-2.1f, 0.05f, 10};
    ASSERT_TRUE(bvh.intersect(ray, hit));
    EXPECT_EQ(hit.geomId, 1u);
    EXPECT_NEAR(hit.t, 9.0f, 1e-4f);
    EXPECT_TRUE(bvh.occluded(ray));
}

// A deforming triangle is hit exactly where interpolateKeys puts it.
TEST(BvhMotion, DeformingTrianglesFollowTheirKeys) {
    Scene scene;
    TriangleMesh quad = testing::makeQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0);
    quad.positionKeys = {quad.positions, quad.positions, quad.positions};
    for (Vec3f& p : quad.positionKeys[1]) p.z = -1.0f;
    for (Vec3f& p : quad.positionKeys[2]) p.z = -5.0f;
    quad.positions = quad.positionKeys.front();
    scene.meshes.push_back(quad);
    const BvhAccelerator bvh(scene);
    Ray ray;
    ray.origin = {0.1f, 0.2f, 1};
    ray.direction = {0, 0, -1};
    ray.tfar = kInf;
    for (float time : {0.0f, 0.25f, 0.5f, 0.6f, 1.0f}) {
        ray.time = time;
        Hit hit;
        ASSERT_TRUE(bvh.intersect(ray, hit)) << time;
        const float z = interpolateKeys(scene.meshes[0].positionKeys, 0, time).z;
        EXPECT_FLOAT_EQ(hit.t, 1.0f - z) << time;
    }
    EXPECT_EQ(bvh.stats().primitiveCount, 2u);
}

}  // namespace
}  // namespace penumbra
