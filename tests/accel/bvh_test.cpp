// Our BVH (accel/bvh_accelerator.h) and Embree on hand-made hard cases, both backends held to
// the same contract (accel/traversal.h); the builder's invariants and determinism; and the two
// backends against each other on a million random rays per scene (tools/crosscheck.h) and on a
// whole render.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "accel/bvh_accelerator.h"
#include "accel/bvh_build.h"
#include "accel/bvh_wide.h"
#include "accel/embree_accelerator.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "scenes/mesh_import.h"
#include "tests/support/any_backend.h"
#include "tests/support/film_comparison.h"
#include "tests/support/scene_builders.h"
#include "tests/support/shared_data.h"
#include "tools/crosscheck.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TriangleMesh makeMesh(std::vector<Vec3f> positions, std::vector<uint32_t> indices) {
    TriangleMesh mesh;
    mesh.name = "test mesh";
    mesh.positions = std::move(positions);
    mesh.indices = std::move(indices);
    return mesh;
}

Sphere makeSphere(Vec3f center, float radius) {
    Sphere s;
    s.name = "test sphere";
    s.center = center;
    s.radius = radius;
    return s;
}

Ray makeRay(Vec3f origin, Vec3f direction, float tnear = 0.0f, float tfar = kInf) {
    Ray r;
    r.origin = origin;
    r.direction = direction;
    r.tnear = tnear;
    r.tfar = tfar;
    return r;
}

// Uniform numbers from a hash, so every case is reproducible.
float uniform(uint64_t test, uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(test, index, dimension) >> 32));
}

const char* kindName(AcceleratorKind kind) { return kind == AcceleratorKind::Bvh ? "Bvh" : "Embree"; }

// Every hard case runs on both backends.
class BothBackends : public ::testing::TestWithParam<AcceleratorKind> {
protected:
    std::unique_ptr<testing::AnyBackend> build(const Scene& scene) {
        return testing::makeBackend(GetParam(), scene);
    }
};

INSTANTIATE_TEST_SUITE_P(Backends, BothBackends,
                         ::testing::Values(AcceleratorKind::Embree, AcceleratorKind::Bvh),
                         [](const auto& info) { return std::string(kindName(info.param)); });

// Rays through points of an edge shared by two triangles, with vertices that are not round
// numbers: points on the edge are not representable, so each ray passes a hair to one side and
// only a watertight test catches all of them. A ray that crosses the surface there (from one side
// of both triangles to the other side of both) must hit one of the two, at the edge.
void expectSharedEdgeHit(const testing::AnyBackend& accel, Vec3f a, Vec3f b, Vec3f normalA, Vec3f normalB,
                         uint64_t test) {
    int misses = 0, tried = 0;
    for (uint64_t i = 0; tried < 20000; ++i) {
        const Vec3f direction = sampleUniformSphere({uniform(test, i, 1), uniform(test, i, 2)});
        const float cosA = dot(direction, normalA), cosB = dot(direction, normalB);
        if (cosA * cosB <= 0.0f || std::abs(cosA) < 0.05f || std::abs(cosB) < 0.05f)
            continue;  // along the ridge
        ++tried;
        const Vec3f onEdge = a + (b - a) * uniform(test, i, 0);
        const float distance = 0.5f + uniform(test, i, 3);
        const Ray ray = makeRay(onEdge - direction * distance, direction);
        Hit hit;
        if (!accel.intersect(ray, hit)) {
            ++misses;
            continue;
        }
        EXPECT_EQ(hit.geomId, 0u);
        EXPECT_LE(hit.primId, 1u);
        EXPECT_NEAR(hit.t, distance, 1e-4f * distance);
        EXPECT_TRUE(accel.occluded(ray));
    }
    EXPECT_EQ(misses, 0) << "rays through the shared edge slipped between its triangles";
}

TEST_P(BothBackends, RaysThroughASharedEdgeHitOneOfItsTriangles) {
    const Vec3f a{0.1234567f, -0.3141592f, 0.2718281f}, b{1.4142135f, 0.5772156f, -0.1618033f};
    // A ridge: the two triangles are not coplanar.
    const Vec3f c{0.9f, -0.8f, 0.45f}, d{0.3f, 1.1f, 0.35f};
    Scene ridge;
    ridge.meshes.push_back(makeMesh({a, b, c, d}, {0, 1, 2, 1, 0, 3}));
    expectSharedEdgeHit(*build(ridge), a, b, normalize(cross(b - a, c - a)), normalize(cross(a - b, d - b)),
                        1);
    // Coplanar: d moved into the plane of a, b, c.
    const Vec3f flatD = a + (a - c) * 0.7f + (b - a) * 0.4f;
    Scene flat;
    flat.meshes.push_back(makeMesh({a, b, c, flatD}, {0, 1, 2, 1, 0, 3}));
    const Vec3f n = normalize(cross(b - a, c - a));
    expectSharedEdgeHit(*build(flat), a, b, n, n, 11);
}

// A closed fan of triangles around a vertex, not planar: rays aimed at the shared vertex hit one.
TEST_P(BothBackends, RaysThroughASharedVertexHitOneOfTheFan) {
    const Vec3f center{0.3183098f, 0.1591549f, -0.2213475f};
    std::vector<Vec3f> positions = {center};
    std::vector<uint32_t> indices;
    constexpr int kSpokes = 7;
    for (int k = 0; k < kSpokes; ++k) {
        const float angle = 2.0f * kPi * float(k) / float(kSpokes) + 0.1f;
        positions.push_back(center + Vec3f{std::cos(angle), std::sin(angle), 0.3f * std::sin(3.0f * angle)});
        indices.insert(indices.end(), {0, uint32_t(1 + k), uint32_t(1 + (k + 1) % kSpokes)});
    }
    Scene scene;
    scene.meshes.push_back(makeMesh(positions, indices));
    const auto accel = build(scene);
    int misses = 0;
    for (uint64_t i = 0; i < 20000; ++i) {
        // From above and below, away from grazing. The fan is not convex: a ray may meet it
        // before it reaches the centre, but never after.
        Vec3f direction = sampleUniformCone({uniform(2, i, 0), uniform(2, i, 1)}, 0.5f);
        if (i % 2) direction = -direction;
        const float distance = 0.25f + uniform(2, i, 2);
        const Ray ray = makeRay(center - direction * distance, direction);
        Hit hit;
        if (!accel->intersect(ray, hit)) {
            ++misses;
            continue;
        }
        EXPECT_LT(hit.primId, uint32_t(kSpokes));
        EXPECT_LE(hit.t, distance * (1.0f + 1e-4f));
    }
    EXPECT_EQ(misses, 0) << "rays through the shared vertex slipped through the fan";
}

TEST_P(BothBackends, RaysParallelToAFaceMissIt) {
    Scene scene;
    scene.meshes.push_back(testing::makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0));
    const auto accel = build(scene);
    Hit hit;
    EXPECT_FALSE(accel->intersect(makeRay({-1.0f, 0.5f, 1e-3f}, {1, 0, 0}), hit)) << "parallel, just above";
    EXPECT_FALSE(accel->intersect(makeRay({-1.0f, 0.5f, -1e-3f}, {1, 0.1f, 0}), hit))
        << "parallel, just below";
    // In the face's own plane: the face has no area seen edge-on, so it is not hit.
    EXPECT_FALSE(accel->intersect(makeRay({-1.0f, 0.5f, 0.0f}, {1, 0, 0}), hit)) << "in the plane";
    EXPECT_FALSE(accel->occluded(makeRay({-1.0f, 0.37f, 0.0f}, {1, 0.01f, 0})));
}

TEST_P(BothBackends, GrazingRaysHitWhereTheyShould) {
    Scene scene;
    scene.meshes.push_back(testing::makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0));
    const auto accel = build(scene);
    for (const float slope : {1e-2f, 1e-3f, 1e-4f}) {
        // Descends onto the plane z = 0 at x = 0.5.
        const Ray ray = makeRay({0.5f - 1.0f, 0.5f, slope}, {1.0f, 0.0f, -slope});
        Hit hit;
        ASSERT_TRUE(accel->intersect(ray, hit)) << "slope " << slope;
        EXPECT_NEAR(hit.t, 1.0f, 1e-3f) << "slope " << slope;
    }
}

// A unit cube with outward faces: rays from inside hit the inside of a wall.
TEST_P(BothBackends, RaysFromInsideAClosedMeshHitItsInside) {
    std::vector<Vec3f> p;
    for (int i = 0; i < 8; ++i)
        p.push_back({(i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f});
    const std::vector<uint32_t> idx = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                       2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    Scene scene;
    scene.meshes.push_back(makeMesh(p, idx));
    const auto accel = build(scene);
    for (uint64_t i = 0; i < 5000; ++i) {
        const Vec3f origin{uniform(3, i, 0) - 0.5f, uniform(3, i, 1) - 0.5f, uniform(3, i, 2) - 0.5f};
        const Vec3f direction = sampleUniformSphere({uniform(3, i, 3), uniform(3, i, 4)});
        const Ray ray = makeRay(origin * 0.99f, direction);
        Hit hit;
        ASSERT_TRUE(accel->intersect(ray, hit)) << "ray " << i << " escaped the closed cube";
        const Vec3f point = ray.at(hit.t);
        EXPECT_NEAR(maxComponent(abs(point)), 0.5f, 1e-5f);
        EXPECT_GT(hit.t, 0.0f);
        EXPECT_TRUE(accel->occluded(ray));
    }
}

TEST_P(BothBackends, DegenerateTrianglesAreNeverHit) {
    Scene scene;
    scene.meshes.push_back(makeMesh({{0, 0, 0},
                                     {1, 0, 0},
                                     {0, 1, 0},  // 0: a real triangle
                                     {5, 5, 0},  // 1: three times the same point
                                     {5, 0, 0},
                                     {6, 0, 0},
                                     {7, 0, 0},  // 2: collinear
                                     {0, 0, 3},
                                     {1, 0, 3},
                                     {0, 1, 3}},  // 3: a real triangle
                                    {0, 1, 2, 3, 3, 3, 4, 5, 6, 7, 8, 9}));
    const auto accel = build(scene);
    Hit hit;
    EXPECT_FALSE(accel->intersect(makeRay({5, 5, 1}, {0, 0, -1}), hit)) << "a point";
    EXPECT_FALSE(accel->intersect(makeRay({5.5f, 0, 1}, {0, 0, -1}), hit)) << "a segment, from across";
    EXPECT_FALSE(accel->intersect(makeRay({5.5f, 1, 0}, {0, -1, 0}), hit))
        << "a segment, from across in its plane";
    EXPECT_FALSE(accel->intersect(makeRay({4, 0, 0}, {1, 0, 0}), hit)) << "a segment, along it";
    EXPECT_FALSE(accel->occluded(makeRay({4, 0, 0}, {1, 0, 0})));
    // The real triangles around them keep their ids.
    ASSERT_TRUE(accel->intersect(makeRay({0.2f, 0.2f, 1}, {0, 0, -1}), hit));
    EXPECT_EQ(hit.primId, 0u);
    ASSERT_TRUE(accel->intersect(makeRay({0.2f, 0.2f, 4}, {0, 0, -1}), hit));
    EXPECT_EQ(hit.primId, 3u);
}

TEST_P(BothBackends, EmptyScenesHitNothing) {
    Scene empty;
    Scene emptyMesh;
    emptyMesh.meshes.push_back(makeMesh({}, {}));
    for (const Scene* scene : {&empty, &emptyMesh}) {
        const auto accel = build(*scene);
        Hit hit;
        EXPECT_FALSE(accel->intersect(makeRay({0, 0, 0}, {0, 0, 1}), hit));
        EXPECT_FALSE(accel->occluded(makeRay({0, 0, 0}, {0, 0, 1})));
    }
}

// Invalid rays hit nothing on both backends (Debian's Embree would abort on a NaN, so the Embree
// backend answers them before calling it).
TEST_P(BothBackends, InvalidRaysHitNothing) {
    Scene scene;
    scene.meshes.push_back(testing::makeQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0));
    scene.spheres.push_back(makeSphere({0, 0, -3}, 1.0f));
    const auto built = build(scene);
    const testing::AnyBackend& accel = *built;
    std::vector<Ray> rays = {makeRay({kNaN, 0, 1}, {0, 0, -1}),
                             makeRay({0, 0, 1}, {0, kNaN, -1}),
                             makeRay({0, 0, 1}, {kNaN, kNaN, kNaN}),
                             makeRay({0, 0, 1}, {0, 0, -1}, kNaN),
                             makeRay({0, 0, 1}, {0, 0, -1}, 0.0f, kNaN),
                             makeRay({kInf, 0, 1}, {0, 0, -1}),
                             makeRay({0, 0, 1}, {0, 0, 0}),
                             makeRay({0, 0, 1}, {0, 0, -1}, 2.0f, 1.0f),
                             makeRay({0, 0, 1}, {0, -kInf, -1}),
                             makeRay({0, 0, 1}, {0, 0, -1}, kInf, kInf)};
    Ray timeless = makeRay({0, 0, 1}, {0, 0, -1});
    timeless.time = kNaN;
    rays.push_back(timeless);
    for (const Ray& ray : rays) {
        Hit hit;
        EXPECT_FALSE(accel.intersect(ray, hit));
        EXPECT_FALSE(accel.occluded(ray));
    }
    Hit hit;
    EXPECT_TRUE(accel.intersect(makeRay({0, 0, 1}, {0, 0, -1}), hit)) << "and a valid ray still hits";
}

TEST_P(BothBackends, TheRayIntervalIsRespected) {
    Scene scene;
    scene.meshes.push_back(testing::makeQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0));
    scene.meshes.push_back(testing::makeQuad({-1, -1, -1}, {2, 0, 0}, {0, 2, 0}, 0));
    const auto accel = build(scene);
    const Vec3f origin{0.3f, 0.2f, 1.0f}, direction{0.0f, 0.0f, -2.0f};  // z = 0 at t = 0.5, z = -1 at t = 1
    Hit hit;
    EXPECT_FALSE(accel->intersect(makeRay(origin, direction, 0.0f, 0.49f), hit));
    EXPECT_FALSE(accel->occluded(makeRay(origin, direction, 0.0f, 0.49f)));
    ASSERT_TRUE(accel->intersect(makeRay(origin, direction, 0.0f, 0.51f), hit));
    EXPECT_NEAR(hit.t, 0.5f, 1e-6f);
    EXPECT_TRUE(accel->occluded(makeRay(origin, direction, 0.0f, 0.51f)));
    ASSERT_TRUE(accel->intersect(makeRay(origin, direction, 0.49f, kInf), hit));
    EXPECT_EQ(hit.geomId, 0u);
    ASSERT_TRUE(accel->intersect(makeRay(origin, direction, 0.51f, kInf), hit));
    EXPECT_EQ(hit.geomId, 1u) << "beyond tnear, the second quad";
    EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
    EXPECT_FALSE(accel->intersect(makeRay(origin, direction, 1.01f, kInf), hit));
    EXPECT_FALSE(accel->intersect(makeRay(origin, -direction), hit)) << "behind the origin";
    if (GetParam() != AcceleratorKind::Bvh) return;
    // Ours computes t = 0.5 exactly here (Embree's reciprocal is an approximation), and both ends
    // of the interval are inclusive.
    ASSERT_TRUE(accel->intersect(makeRay(origin, direction, 0.0f, 0.5f), hit)) << "tfar is inclusive";
    EXPECT_EQ(hit.t, 0.5f);
    ASSERT_TRUE(accel->intersect(makeRay(origin, direction, 0.5f, kInf), hit)) << "tnear is inclusive";
    EXPECT_EQ(hit.geomId, 0u);
}

TEST_P(BothBackends, SpheresFromOutsideAndInside) {
    Scene scene;
    scene.meshes.push_back(testing::makeQuad({10, 10, 10}, {1, 0, 0}, {0, 1, 0}, 0));  // out of the way
    scene.spheres.push_back(makeSphere({-5, 0, 0}, 1.0f));
    scene.spheres.push_back(makeSphere({1, 2, 3}, 0.5f));
    const auto accel = build(scene);
    const uint32_t sphereGeomId = uint32_t(scene.meshes.size());
    Hit hit;
    ASSERT_TRUE(accel->intersect(makeRay({-2, 2, 3}, {1, 0, 0}), hit)) << "from outside";
    EXPECT_EQ(hit.geomId, sphereGeomId);
    EXPECT_EQ(hit.primId, 1u);
    EXPECT_NEAR(hit.t, 2.5f, 1e-5f);
    EXPECT_EQ(hit.u, 0.0f);
    EXPECT_EQ(hit.v, 0.0f);
    EXPECT_GT(dot(normalize(hit.geometricNormal), Vec3f{-1, 0, 0}), 0.9999f)
        << "normal: hit point minus centre";

    ASSERT_TRUE(accel->intersect(makeRay({1, 2, 3}, {0, 0, 2}), hit)) << "from the centre";
    EXPECT_EQ(hit.primId, 1u);
    EXPECT_NEAR(hit.t, 0.25f, 1e-6f) << "leaves through the far side (direction has length 2)";
    EXPECT_TRUE(accel->occluded(makeRay({1, 2, 3}, {0, 0, 1})));

    EXPECT_FALSE(accel->intersect(makeRay({-2, 2, 3}, {-1, 0, 0}), hit)) << "behind";
    EXPECT_FALSE(accel->intersect(makeRay({-2, 2.6f, 3}, {1, 0, 0}), hit)) << "passes by";
    EXPECT_FALSE(accel->occluded(makeRay({-2, 2, 3}, {1, 0, 0}, 0.0f, 2.4f))) << "ends before it";

    // A small sphere far from the origin: the naive discriminant would lose it.
    Scene far;
    far.spheres.push_back(makeSphere({1000, 1000, 1000}, 0.01f));
    const auto farAccel = build(far);
    ASSERT_TRUE(farAccel->intersect(makeRay({1000.003f, 1000, 990}, {0, 0, 1}), hit));
    EXPECT_NEAR(hit.t, 10.0f - std::sqrt(0.01f * 0.01f - 0.003f * 0.003f), 2e-3f);
}

TEST_P(BothBackends, HitsFollowEmbreesConventions) {
    const Vec3f p0{0.2f, -0.1f, 0.5f}, p1{1.3f, 0.2f, 0.4f}, p2{0.4f, 1.1f, 0.6f};
    Scene scene;
    scene.meshes.push_back(testing::makeQuad({-5, -5, -5}, {1, 0, 0}, {0, 1, 0}, 0));
    scene.meshes.push_back(makeMesh({{9, 9, 9}, {9, 9, 8}, {9, 8, 9}, p0, p1, p2}, {0, 1, 2, 3, 4, 5}));
    const auto accel = build(scene);
    const Vec3f target = p0 * 0.2f + p1 * 0.3f + p2 * 0.5f;
    const Ray ray = makeRay(target + Vec3f{0.1f, 0.2f, 2.0f}, Vec3f{-0.1f, -0.2f, -2.0f});
    Hit hit;
    ASSERT_TRUE(accel->intersect(ray, hit));
    EXPECT_EQ(hit.geomId, 1u);
    EXPECT_EQ(hit.primId, 1u);
    EXPECT_NEAR(hit.u, 0.3f, 1e-5f) << "u is the barycentric of vertex 1";
    EXPECT_NEAR(hit.v, 0.5f, 1e-5f) << "v is the barycentric of vertex 2";
    EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
    const Vec3f n = normalize(cross(p1 - p0, p2 - p0));
    EXPECT_GT(std::abs(dot(normalize(hit.geometricNormal), n)), 0.9999f);
}

// ---------------------------------------------------------------------------------------------
// The builder.

std::vector<Bounds3f> randomTriangleBounds(size_t count, uint64_t seed) {
    std::vector<Bounds3f> bounds(count);
    for (size_t i = 0; i < count; ++i) {
        const Vec3f c{uniform(seed, i, 0), uniform(seed, i, 1), uniform(seed, i, 2)};
        Bounds3f b;
        b.extend(c);
        b.extend(c + Vec3f{uniform(seed, i, 3), uniform(seed, i, 4), uniform(seed, i, 5)} * 0.02f);
        bounds[i] = b;
    }
    return bounds;
}

void expectWellFormed(const BvhBuildResult& bvh, const std::vector<Bounds3f>& input, int maxLeafSize) {
    ASSERT_FALSE(bvh.nodes.empty());
    EXPECT_EQ(reinterpret_cast<uintptr_t>(bvh.nodes.data()) % 64, 0u) << "sibling pairs share a cache line";
    std::vector<int> seen(input.size(), 0);
    for (uint32_t i : bvh.primitiveOrder) ++seen.at(i);
    for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i;
    EXPECT_LT(bvh.maxDepth, kBvhMaxDepth);

    auto contains = [](const BvhNode& outer, const float* b) {
        for (int k = 0; k < 3; ++k)
            if (b[k] < outer.bounds[k] || b[3 + k] > outer.bounds[3 + k]) return false;
        return true;
    };
    size_t leafPrimitives = 0;
    for (size_t n = 0; n < bvh.nodes.size(); ++n) {
        if (n == 1) continue;  // padding
        const BvhNode& node = bvh.nodes[n];
        if (node.isLeaf()) {
            EXPECT_LE(node.count, maxLeafSize);
            leafPrimitives += node.count;
            for (uint32_t i = node.offset; i < node.offset + node.count; ++i) {
                const Bounds3f& b = input[bvh.primitiveOrder[i]];
                const float box[6] = {b.lower.x, b.lower.y, b.lower.z, b.upper.x, b.upper.y, b.upper.z};
                ASSERT_TRUE(contains(node, box)) << "leaf " << n << " does not hold its primitive";
            }
        } else {
            ASSERT_EQ(node.offset % 2, 0u);
            ASSERT_LT(node.offset + 1, bvh.nodes.size());
            ASSERT_GT(node.offset, n) << "children come after their parent";
            for (uint32_t c = node.offset; c < node.offset + 2; ++c)
                ASSERT_TRUE(contains(node, bvh.nodes[c].bounds))
                    << "node " << n << " does not hold child " << c;
        }
    }
    EXPECT_EQ(leafPrimitives, input.size());
}

TEST(BvhBuild, TreesAreWellFormed) {
    for (size_t count : {1u, 2u, 5u, 100u, 20000u}) {
        const auto input = randomTriangleBounds(count, count);
        expectWellFormed(buildBvh(input), input, BvhBuildSettings{}.maxLeafSize);
    }
}

TEST(BvhBuild, CoincidentAndExponentiallySpreadPrimitivesStayShallow) {
    // Every centroid the same: no SAH split exists, so splits fall back to the median.
    std::vector<Bounds3f> same(5000, Bounds3f{{0, 0, 0}, {1, 1, 1}});
    expectWellFormed(buildBvh(same), same, BvhBuildSettings{}.maxLeafSize);
    // Boxes at 2^-i: SAH peels one off per level, so the depth limit has to step in.
    std::vector<Bounds3f> spread;
    for (int i = 0; i < 120; ++i) {
        const float x = std::ldexp(1.0f, -i);
        spread.push_back({{x, 0, 0}, {x * 1.5f, 1e-30f, 1e-30f}});
    }
    const BvhBuildResult bvh = buildBvh(spread);
    expectWellFormed(bvh, spread, BvhBuildSettings{}.maxLeafSize);
    EXPECT_LT(bvh.maxDepth, kBvhMaxDepth);
}

TEST(BvhBuild, TheTreeDoesNotDependOnTheThreadCount) {
    const auto input = randomTriangleBounds(200000, 7);
    BvhBuildResult one, many;
    tbb::task_arena(1).execute([&] { one = buildBvh(input); });
    tbb::task_arena(4).execute([&] { many = buildBvh(input); });
    ASSERT_EQ(one.nodes.size(), many.nodes.size());
    EXPECT_EQ(std::memcmp(one.nodes.data(), many.nodes.data(), one.nodes.size() * sizeof(BvhNode)), 0);
    EXPECT_EQ(one.primitiveOrder, many.primitiveOrder);
}

// The 4-wide tree: every primitive in exactly one leaf, inside its leaf's box; every interior
// child's boxes inside the box its parent holds for it; 2 to 4 children a node (1 for a tree that
// is a single leaf); no deeper than the binary tree.
void expectWellFormedWide(const Bvh4& wide, const BvhBuildResult& binary,
                          const std::vector<Bounds3f>& input) {
    ASSERT_FALSE(wide.nodes.empty());
    EXPECT_EQ(reinterpret_cast<uintptr_t>(wide.nodes.data()) % 64, 0u) << "nodes start on a cache line";
    EXPECT_LE(wide.maxDepth, binary.maxDepth);
    auto contains = [](const Bounds3f& outer, const Bounds3f& inner) {
        for (int k = 0; k < 3; ++k)
            if (inner.lower[k] < outer.lower[k] || inner.upper[k] > outer.upper[k]) return false;
        return true;
    };
    std::vector<int> seen(input.size(), 0);
    std::vector<int> parents(wide.nodes.size(), 0);
    size_t leaves = 0;
    for (size_t n = 0; n < wide.nodes.size(); ++n) {
        const Bvh4Node& node = wide.nodes[n];
        int children = 0;
        for (int i = 0; i < kBvhWidth; ++i) {
            const Bounds3f box = node.childBounds(i);
            if (node.child[i] == kBvhEmptySlot) {
                EXPECT_TRUE(box.isEmpty()) << "node " << n << " slot " << i;
                continue;
            }
            ++children;
            ASSERT_TRUE(contains(wide.bounds, box));
            if (node.isLeaf(i)) {
                ++leaves;
                EXPECT_LE(node.count[i], BvhBuildSettings{}.maxLeafSize);
                for (uint32_t p = node.child[i]; p < node.child[i] + node.count[i]; ++p) {
                    const uint32_t primitive = binary.primitiveOrder.at(p);
                    ++seen[primitive];
                    ASSERT_TRUE(contains(box, input[primitive])) << "leaf does not hold its primitive";
                }
            } else {
                ASSERT_GT(node.child[i], n) << "children come after their parent";
                ASSERT_LT(node.child[i], wide.nodes.size());
                ++parents[node.child[i]];
                const Bvh4Node& c = wide.nodes[node.child[i]];
                for (int j = 0; j < kBvhWidth; ++j) {
                    if (c.child[j] == kBvhEmptySlot) continue;
                    ASSERT_TRUE(contains(box, c.childBounds(j))) << "node " << n << " child " << i;
                }
            }
        }
        EXPECT_LE(children, kBvhWidth);
        EXPECT_GE(children, binary.nodes[0].isLeaf() ? 1 : 2) << "node " << n;
    }
    for (size_t n = 1; n < parents.size(); ++n) ASSERT_EQ(parents[n], 1) << "node " << n;
    for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i;
    EXPECT_EQ(leaves, wide.leafCount);
}

TEST(BvhBuild, WideTreesAreWellFormed) {
    for (size_t count : {1u, 2u, 5u, 100u, 20000u}) {
        const auto input = randomTriangleBounds(count, count);
        const BvhBuildResult binary = buildBvh(input);
        const Bvh4 wide = collapseToBvh4(binary);
        expectWellFormedWide(wide, binary, input);
        if (count >= 100) {
            // Opening the widest child first fills nodes: well under half the binary node count.
            EXPECT_LT(wide.nodes.size(), binary.nodes.size() / 2);
            EXPECT_LT(wide.maxDepth, binary.maxDepth);
        }
    }
    std::vector<Bounds3f> same(5000, Bounds3f{{0, 0, 0}, {1, 1, 1}});
    const BvhBuildResult binary = buildBvh(same);
    expectWellFormedWide(collapseToBvh4(binary), binary, same);
}

TEST(BvhBuild, TheWideTreeDoesNotDependOnTheThreadCount) {
    const auto input = randomTriangleBounds(200000, 8);
    Bvh4 one, many;
    tbb::task_arena(1).execute([&] { one = collapseToBvh4(buildBvh(input)); });
    tbb::task_arena(4).execute([&] { many = collapseToBvh4(buildBvh(input)); });
    ASSERT_EQ(one.nodes.size(), many.nodes.size());
    EXPECT_EQ(std::memcmp(one.nodes.data(), many.nodes.data(), one.nodes.size() * sizeof(Bvh4Node)), 0);
}

TEST(BvhAccelerator, AcceptsMovingScenes) {
    // Motion blur is handled (tests/scenes/bvh_motion_test.cpp); a moving sphere is found where
    // its motion puts it.
    Scene scene;
    scene.spheres.push_back(makeSphere({0, 0, 0}, 1.0f));
    scene.spheres[0].motion.keys.resize(2);
    scene.spheres[0].motion.keys[1].translation = {4, 0, 0};
    const BvhAccelerator bvh(scene);
    Ray ray = makeRay({4, 0, 5}, {0, 0, -1});
    Hit hit;
    ray.time = 1.0f;
    ASSERT_TRUE(bvh.intersect(ray, hit));
    EXPECT_NEAR(hit.t, 4.0f, 1e-5f);
    EXPECT_EQ(hit.geomId, 0u);
    EXPECT_EQ(hit.primId, 0u);
    ray.time = 0.0f;
    EXPECT_FALSE(bvh.intersect(ray, hit));
    EXPECT_FALSE(bvh.occluded(ray));
}

// ---------------------------------------------------------------------------------------------
// Ours against Embree.

// 10^6 rays, a quarter each of camera, bounce, shadow and random rays (see tools/crosscheck.h).
// Scanned meshes can hold overlapping coplanar triangles, where either answer is right: for them
// ties count as agreements.
void expectAgreement(const Scene& scene, const char* what, bool countTies = false,
                     uint64_t rays = 1'000'000) {
    CrosscheckOptions options;
    options.rays = rays;
    options.measureThroughput = false;
    const CrosscheckReport report = runCrosscheck(scene, options);
    EXPECT_EQ(report.unexplained(), 0u) << what << "\n" << formatCrosscheckText(report);
    EXPECT_GT(countTies ? report.agreementRatioCountingTies() : report.agreementRatio(), 0.9999)
        << what << "\n"
        << formatCrosscheckText(report);
    EXPECT_EQ(report.rayCount, rays);
    EXPECT_LT(report.maxPointDistance, 1e-4) << what;
    std::printf(
        "%s: agreement %.5f%% (%.5f%% counting ties), %llu mismatches (%llu ties), t differs by at most %.3g "
        "(mean %.3g)\n",
        what, 100.0 * report.agreementRatio(), 100.0 * report.agreementRatioCountingTies(),
        (unsigned long long)(report.hitMissDisagreements + report.primitiveDisagreements),
        (unsigned long long)report.mismatchesByKind[size_t(MismatchKind::Tie)], report.maxRelativeDistance,
        report.meanRelativeDistance);
}

// A camera looking at the whole of the scene's only mesh.
void frameMesh(Scene& scene) {
    Bounds3f b;
    for (const Vec3f& p : scene.meshes.front().positions) b.extend(p);
    const Vec3f center = b.centroid();
    const float radius = 0.5f * length(b.upper - b.lower);
    scene.camera.lookAt = center;
    scene.camera.lookFrom = center + Vec3f{0.3f, 0.2f, 1.0f} * (2.2f * radius);
    scene.film.width = scene.film.height = 256;
}

std::optional<Scene> loadMeshScene(const char* file) {
    const fs::path path = fs::path(PENUMBRA_DATA_DIR) / "meshes" / file;
    if (!fs::exists(path)) return std::nullopt;
    Scene scene;
    scene.sourcePath = path;
    scene.meshes.push_back(importMesh(path));
    frameMesh(scene);
    return scene;
}

TEST(BvhAgainstEmbree, BoxSceneOnAMillionRays) {
    expectAgreement(testing::makeSmallBoxScene(64, 64, 1), "box scene");
}

TEST(BvhAgainstEmbree, StanfordBunnyOnAMillionRays) {
    const auto scene = loadMeshScene("stanford-bunny.obj");
    if (!scene)
        GTEST_SKIP() << testing::sharedDataMissing(std::string(PENUMBRA_DATA_DIR) +
                                                   "/meshes/stanford-bunny.obj");
    expectAgreement(*scene, "stanford bunny");
}

TEST(BvhAgainstEmbree, StanfordDragonOnAMillionRays) {
    const auto scene = loadMeshScene("dragon_vrip_res2.ply.gz");
    if (!scene)
        GTEST_SKIP() << testing::sharedDataMissing(std::string(PENUMBRA_DATA_DIR) +
                                                   "/meshes/dragon_vrip_res2.ply.gz");
    // This mesh has overlapping triangles (about 1 ray in 5000 meets two at the same distance).
    expectAgreement(*scene, "stanford dragon (res2)", /*countTies=*/true);
}

// The scene's film rendered with Embree and with our BVH, and their comparison (printed).
struct BackendFilms {
    Film embree, bvh;
    testing::FilmComparison comparison;
};
BackendFilms renderOnBothBackends(const Scene& scene) {
    BackendFilms films{
        Film(scene.film.width, scene.film.height), Film(scene.film.width, scene.film.height), {}};
    RenderOptions options;
    options.accelerator = AcceleratorKind::Embree;
    render(scene, options, films.embree);
    options.accelerator = AcceleratorKind::Bvh;
    render(scene, options, films.bvh);
    films.comparison = testing::compareWithinNoise(films.embree, films.bvh);
    const testing::FilmComparison& c = films.comparison;
    std::printf("render: %d of %d pixels bit-identical, image means %.6f (embree) and %.6f (bvh)\n",
                c.identicalPixels, scene.film.width * scene.film.height, c.meanA, c.meanB);
    return films;
}

// The whole renderer on both backends. Each hit's t and barycentrics are recomputed from the
// primitive found (canonicalizeHit), so wherever both backends find the same primitives the films
// are the same bit for bit; in this box every ray's hit agrees.
TEST(BvhAgainstEmbree, RendersAreBitIdenticalWhereEveryHitAgrees) {
    const BackendFilms films = renderOnBothBackends(testing::makeSmallBoxScene(32, 32, 32));
    EXPECT_TRUE(films.embree.identicalTo(films.bvh));
    EXPECT_EQ(films.comparison.outlierChannels, 0);
    EXPECT_GT(films.comparison.meanA, 0.0);
}

// With canonical hits off, Embree's own t and barycentrics are shaded: the films differ in the last
// bits (Embree rounds its Pluecker-form test differently) but agree within noise. Every path still
// meets the same primitives, only its shading points move by a few float ulps (~1e-7 relative), and
// radiance varies smoothly with them (distances, cosines), so the image means may differ by about
// 1e-6 relative; 1e-4 leaves a hundredfold margin.
TEST(BvhAgainstEmbree, WithoutCanonicalHitsRendersAgreeWithinNoise) {
    Scene scene = testing::makeSmallBoxScene(32, 32, 32);
    scene.settings.canonicalHits = false;
    const BackendFilms films = renderOnBothBackends(scene);
    const testing::FilmComparison& c = films.comparison;
    EXPECT_FALSE(films.embree.identicalTo(films.bvh));  // the setting took effect
    EXPECT_EQ(c.outlierChannels, 0);
    EXPECT_NEAR(c.meanA, c.meanB, 1e-4 * c.meanB);
}

}  // namespace
}  // namespace penumbra
