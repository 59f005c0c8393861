// The table of still triangles' normals and shading frames (geometry/face_frames.h) against those
// computed at the hit: the same bits, so that shading with the table changes nothing.
#include "geometry/face_frames.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "geometry/surface_interaction.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

bool sameBits(Vec3f a, Vec3f b) { return std::memcmp(&a, &b, sizeof(Vec3f)) == 0; }
bool sameBits(const Frame& a, const Frame& b) {
    return sameBits(a.s, b.s) && sameBits(a.t, b.t) && sameBits(a.n, b.n);
}

// A still mesh of random triangles (the last one degenerate: its three vertices on a line), a
// moving copy of it, a sphere, and a still copy with vertex normals.
Scene makeScene() {
    Scene scene;
    scene.materials = {testing::makeLambert(Rgb(0.5f))};
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
    TriangleMesh smooth = mesh;
    for (size_t v = 0; v < smooth.positions.size(); ++v)
        smooth.normals.push_back(normalize(Vec3f{1.0f, float(v % 7), 2.0f}));
    scene.meshes.push_back(smooth);
    return scene;
}

TEST(FaceFrames, AreTheNormalsAndFramesComputedAtTheHit) {
    const Scene scene = makeScene();
    const FaceFrames frames(scene);
    const TriangleMesh& mesh = scene.meshes[0];
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const Frame* frame = frames.find(0, t);
        ASSERT_NE(frame, nullptr);
        const Vec3f* n = &frame->n;
        const Vec3f p0 = mesh.positions[mesh.indices[3 * t]], p1 = mesh.positions[mesh.indices[3 * t + 1]],
                    p2 = mesh.positions[mesh.indices[3 * t + 2]];
        EXPECT_TRUE(sameBits(*n, triangleNormal(p0, p1, p2))) << "triangle " << t;
        EXPECT_TRUE(sameBits(*frame, Frame::fromNormal(*n))) << "triangle " << t;
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
    EXPECT_EQ(frames.find(1, 0), nullptr) << "a moving mesh's normals change over the shutter";
    EXPECT_NE(frames.find(2, 0), nullptr) << "a still mesh with vertex normals has face normals too";
    EXPECT_EQ(frames.find(3, 0), nullptr) << "a sphere is not a mesh";
}

TEST(FaceFrames, ShadingWithTheTableIsBitIdentical) {
    const Scene scene = makeScene();
    const FaceFrames frames(scene);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int degenerate = 0;
    for (const uint32_t geomId : {0u, 2u}) {
        for (uint32_t t = 0; t < scene.meshes[geomId].triangleCount(); ++t) {
            Hit hit;
            hit.geomId = geomId;
            hit.primId = t;
            hit.u = 0.5f * u(rng);
            hit.v = 0.5f * u(rng);
            hit.t = 1.0f;
            Ray ray;
            ray.origin = {20.0f * u(rng) - 10.0f, 20.0f, 5.0f};
            ray.direction = {u(rng) - 0.5f, -1.0f, u(rng) - 0.5f};
            Hit withTable = hit, without = hit;
            const SurfaceInteraction a = resolveHit<true>(scene, ray, withTable, &frames);
            const SurfaceInteraction b = resolveHit<true>(scene, ray, without);
            EXPECT_TRUE(sameBits(a.position, b.position)) << "triangle " << t;
            EXPECT_TRUE(sameBits(a.geometricNormal, b.geometricNormal)) << "triangle " << t;
            EXPECT_TRUE(sameBits(a.shadingNormal, b.shadingNormal)) << "triangle " << t;
            EXPECT_EQ(b.shadingFrame, nullptr) << "without the table there is no frame";
            const bool isDegenerate = t + 1 == scene.meshes[geomId].triangleCount();
            if (geomId == 0 && !isDegenerate) {
                // The integrator's frame, taken from the table: the same bits as building it at the hit.
                ASSERT_NE(a.shadingFrame, nullptr) << "triangle " << t;
                EXPECT_TRUE(sameBits(*a.shadingFrame, Frame::fromNormal(b.shadingNormal)))
                    << "triangle " << t;
            } else {
                // Vertex normals make a shading normal of their own; a degenerate triangle has none.
                EXPECT_EQ(a.shadingFrame, nullptr) << "mesh " << geomId << ", triangle " << t;
            }
            if (isDegenerate) {
                // No normal: both face the ray.
                EXPECT_TRUE(sameBits(a.geometricNormal, normalize(-ray.direction)));
                ++degenerate;
            }
        }
    }
    EXPECT_EQ(degenerate, 2);
}

}  // namespace
}  // namespace penumbra
