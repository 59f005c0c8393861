// The table of still triangles' normals (renderer/face_normals.h) against the normal computed at
// the hit: the same bits, so that shading with the table changes nothing.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "renderer/face_normals.h"
#include "renderer/surface_interaction.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

bool sameBits(Vec3f a, Vec3f b) { return std::memcmp(&a, &b, sizeof(Vec3f)) == 0; }

// A still mesh of random triangles (the last one degenerate: its three vertices on a line), a
// moving copy of it, and a sphere.
Scene makeScene() {
    Scene scene;
    scene.materials = {testing::makeLambert("white", Rgb(0.5f))};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    TriangleMesh mesh;
    mesh.name = "random";
    for (int t = 0; t < 200; ++t) {
        for (int k = 0; k < 3; ++k) {
            mesh.indices.push_back(uint32_t(mesh.positions.size()));
            mesh.positions.push_back({u(rng), u(rng), u(rng)});
        }
    }
    const Vec3f a{1.0f, 2.0f, 3.0f}, d{0.5f, -1.0f, 2.0f};
    for (const float s : {0.0f, 1.0f, 3.0f}) {
        mesh.indices.push_back(uint32_t(mesh.positions.size()));
        mesh.positions.push_back(a + d * s);
    }
    scene.meshes.push_back(mesh);
    TriangleMesh moving = mesh;
    moving.motion.keys.resize(2);
    moving.motion.keys[1].translation = {0.0f, 1.0f, 0.0f};
    scene.meshes.push_back(moving);
    scene.spheres.push_back(Sphere{"ball", {0.0f, 0.0f, 0.0f}, 1.0f, 0, {}, {}});
    return scene;
}

TEST(FaceNormals, AreTheNormalsComputedAtTheHit) {
    const Scene scene = makeScene();
    const FaceNormals normals(scene);
    const TriangleMesh& mesh = scene.meshes[0];
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3f* n = normals.find(0, t);
        ASSERT_NE(n, nullptr);
        const Vec3f p0 = mesh.positions[mesh.indices[3 * t]], p1 = mesh.positions[mesh.indices[3 * t + 1]],
                    p2 = mesh.positions[mesh.indices[3 * t + 2]];
        EXPECT_TRUE(sameBits(*n, triangleNormal(p0, p1, p2))) << "triangle " << t;
        if (t + 1 < mesh.triangleCount()) {
            // Unit length and on the front side, cross(p1 - p0, p2 - p0). The tolerance: n * (1 / |n|)
            // is off by at most about 3 float ulps (the dot product's 2.5 halved by the square root,
            // then the reciprocal and the product), and length() here adds about 2 more: 5 * 2^-24
            // ~ 3e-7, so 1e-6 leaves a threefold margin.
            EXPECT_NEAR(length(*n), 1.0f, 1e-6f) << "triangle " << t;
            EXPECT_GT(dot(*n, cross(p1 - p0, p2 - p0)), 0.0f) << "triangle " << t;
        } else {
            EXPECT_TRUE(sameBits(*n, Vec3f{0.0f, 0.0f, 0.0f})) << "the degenerate triangle";
        }
    }
    EXPECT_EQ(normals.find(1, 0), nullptr) << "a moving mesh's normals change over the shutter";
    EXPECT_EQ(normals.find(2, 0), nullptr) << "a sphere is not a mesh";
}

TEST(FaceNormals, ShadingWithTheTableIsBitIdentical) {
    const Scene scene = makeScene();
    const FaceNormals normals(scene);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int degenerate = 0;
    for (uint32_t t = 0; t < scene.meshes[0].triangleCount(); ++t) {
        Hit hit;
        hit.geomId = 0;
        hit.primId = t;
        hit.u = 0.5f * u(rng);
        hit.v = 0.5f * u(rng);
        hit.t = 1.0f;
        Ray ray;
        ray.origin = {20.0f * u(rng) - 10.0f, 20.0f, 5.0f};
        ray.direction = {u(rng) - 0.5f, -1.0f, u(rng) - 0.5f};
        Hit withTable = hit, without = hit;
        const SurfaceInteraction a = resolveHit<true>(scene, ray, withTable, &normals);
        const SurfaceInteraction b = resolveHit<true>(scene, ray, without);
        EXPECT_TRUE(sameBits(a.position, b.position)) << "triangle " << t;
        EXPECT_TRUE(sameBits(a.geometricNormal, b.geometricNormal)) << "triangle " << t;
        EXPECT_TRUE(sameBits(a.shadingNormal, b.shadingNormal)) << "triangle " << t;
        if (t + 1 == scene.meshes[0].triangleCount()) {
            // No normal: both face the ray.
            EXPECT_TRUE(sameBits(a.geometricNormal, normalize(-ray.direction)));
            ++degenerate;
        }
    }
    EXPECT_EQ(degenerate, 1);
}

}  // namespace
}  // namespace penumbra
