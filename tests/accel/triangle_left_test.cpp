// The triangle a ray leaves (TriangleLeft, geometry/hit.h): Embree skips it, on still meshes,
// moving meshes and instances, and so no longer meets it again by rounding; our BVH needs no help.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "scenes/scene_loader.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

// A floor quad (z = 0) under a ceiling quad (z = 1), as a still mesh (ids 0 and 1), or with the
// floor a moving mesh or an instance of a prototype (its id then the instance's, 2).
enum class FloorKind { Still, Moving, Instance };

Scene floorAndCeiling(FloorKind kind) {
    Scene scene;
    scene.materials.push_back(testing::makeLambert(Rgb(0.5f)));
    TriangleMesh floor = testing::makeQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0);
    TriangleMesh ceiling = testing::makeQuad({-1, -1, 1}, {2, 0, 0}, {0, 2, 0}, 0);
    if (kind == FloorKind::Moving) {
        TransformKey a, b;
        b.translation = {0.0f, 0.0f, 0.0f};
        floor.motion.keys = {a, b};
    }
    if (kind == FloorKind::Instance) {
        scene.meshes.push_back(testing::makeQuad({5, 5, 5}, {1, 0, 0}, {0, 1, 0}, 0));  // elsewhere
        scene.meshes.push_back(ceiling);
        scene.prototypes.push_back(floor);
        MeshInstance instance;
        instance.prototype = 0;
        instance.placement = Transform::translate({0, 0, 0});
        scene.instances.push_back(instance);
    } else {
        scene.meshes.push_back(floor);
        scene.meshes.push_back(ceiling);
    }
    return scene;
}

// A ray from below the floor, up through triangle `prim` of the floor to the ceiling: with the
// floor's triangle named as the one it leaves, Embree skips that triangle (a ray that really left
// it could not meet it) and finds the ceiling; unnamed, or another triangle named, it finds the floor.
TEST(TriangleLeft, EmbreeSkipsTheNamedTriangleOnStillMovingAndInstancedMeshes) {
    for (FloorKind kind : {FloorKind::Still, FloorKind::Moving, FloorKind::Instance}) {
        const Scene scene = floorAndCeiling(kind);
        const EmbreeAccelerator embree(scene);
        const uint32_t floorId = kind == FloorKind::Instance ? scene.instanceGeomId(0) : 0;
        const uint32_t ceilingId = 1;
        Ray ray;
        ray.origin = {0.5f, -0.25f, -0.5f};  // under the floor's second triangle
        ray.direction = {0, 0, 1};
        ray.time = 0.5f;
        Hit unnamed;
        ASSERT_TRUE(embree.intersect(ray, unnamed)) << int(kind);
        ASSERT_EQ(unnamed.geomId, floorId) << int(kind);
        const uint32_t prim = unnamed.primId;
        Hit hit;
        ASSERT_TRUE(embree.intersect(ray, hit, TriangleLeft{floorId, prim})) << int(kind);
        EXPECT_EQ(hit.geomId, ceilingId) << int(kind);
        EXPECT_NEAR(hit.t, 1.5f, 1e-6f) << int(kind);
        ASSERT_TRUE(embree.intersect(ray, hit, TriangleLeft{floorId, 1 - prim})) << int(kind);
        EXPECT_EQ(hit.geomId, floorId) << int(kind);
        // A segment ending between floor and ceiling is blocked only by the floor.
        Ray segment = ray;
        segment.tfar = 1.0f;
        EXPECT_TRUE(embree.occluded(segment)) << int(kind);
        EXPECT_FALSE(embree.occluded(segment, TriangleLeft{floorId, prim})) << int(kind);
        EXPECT_TRUE(embree.occluded(segment, TriangleLeft{ceilingId, prim})) << int(kind);
    }
}

// The rays of `penumbra crosscheck --rays 200000`, seeds 0 to 4, on which Embree met the triangle
// the ray leaves (the Cornell box's short box, mesh 5, triangle 10), at the scales of
// coordinate_scale_test (docs/limits.md). Their origins lie on the side their direction leaves
// towards, 0.46 to 0.79 ulps of the triangle's extent off its plane: a hit on it is rounding.
struct RecordedRay {
    float scale;
    Vec3f origin, direction;
    float tfar, time;
    bool segment;  // a shadow ray, traced with occluded()
};
constexpr float kInf = std::numeric_limits<float>::infinity();
const RecordedRay kRays[] = {
    {1.0f,
     {0x1.08cd0ep-3, 0x1.bc157ap-2, 0x1.2e446cp-8},
     {0x1.cf852p-1, -0x1.85ac7ap-2, 0x1.826786p-3},
     kInf,
     0x1.1f7042p-1,
     false},
    {1e-6f,
     {0x1.461a52p-23, 0x1.1e4178p-21, 0x1.861b9p-27},
     {0x1.6a00d4p-3, -0x1.4b33bep-2, -0x1.dbf394p-1},
     kInf,
     0x1.3e9eaep-1,
     false},
    {1e-6f,
     {0x1.4083a2p-23, 0x1.162eeap-21, 0x1.6b621p-27},
     {-0x1.3a4b8ap-2, 0x1.7593c8p-4, -0x1.e50b58p-1},
     kInf,
     0x1.7ba99p-3,
     false},
    {1e-6f,
     {0x1.418832p-23, 0x1.cbf38ep-23, 0x1.70400ep-27},
     {0x1.64e84p-6, -0x1.113e2cp-2, -0x1.ed4f34p-1},
     kInf,
     0x1.74884p-1,
     false},
    {1e-6f,
     {0x1.252a22p-23, 0x1.3d4f08p-21, 0x1.d13268p-28},
     {0x1.30f784p-1, 0x1.5c744p-1, -0x1.b4e4b8p-2},
     kInf,
     0x1.423644p-2,
     false},
    {1e2f,
     {0x1.9399f8p+3, 0x1.411e48p+2, 0x1.7738aep-2},
     {-0x1.5a5d3ap+2, 0x1.d71954p+3, 0x1.16ce84p+4},
     0x1.ffffep-1,
     0x1.99f714p-1,
     true},
    {1e5f,
     {0x1.891aeap+13, 0x1.5af05ap+15, 0x1.6482bep+8},
     {-0x1.de12ep+10, 0x1.fef88p+10, 0x1.6ccdaap+12},
     0x1.ffffep-1,
     0x1.9f3c0cp-1,
     true},
    {1e5f,
     {0x1.8773c2p+13, 0x1.559738p+14, 0x1.54b3bap+8},
     {0x1.2ca8b8p+11, 0x1.29f456p+15, 0x1.6ca0ap+13},
     0x1.ffffep-1,
     0x1.1b7538p-1,
     true},
    {1e7f,
     {0x1.45a914p+20, 0x1.865d6ep+21, 0x1.c7e75p+15},
     {-0x1.e195f8p-3, 0x1.9b4962p-5, -0x1.f0fa92p-1},
     kInf,
     0x1.f043b8p-2,
     false},
};

// The Cornell box with every length times `factor`, as coordinate_scale_test scales it.
Scene cornellBoxAtScale(float factor) {
    Scene scene = loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "scenes" / "cornell-box.json");
    for (TriangleMesh& mesh : scene.meshes)
        for (Vec3f& p : mesh.positions) p = p * factor;
    return scene;
}

// Leaving the short box's triangle, each ray gets the answer of our BVH (whose triangle test
// rejects hits within its error bound on t): the same primitive, or the same occlusion. Without
// the triangle named, Embree met it again on this machine's instruction set for all nine
// (printed, not asserted: Embree chooses its kernels by the CPU).
TEST(TriangleLeft, EmbreeNoLongerMeetsTheTriangleARayLeavesOnTheScaledCornellBox) {
    const TriangleLeft left{5, 10};
    std::map<float, Scene> scenes;
    int metAgainUnnamed = 0;
    for (const RecordedRay& r : kRays) {
        auto [it, added] = scenes.try_emplace(r.scale);
        if (added) it->second = cornellBoxAtScale(r.scale);
        const Scene& scene = it->second;
        const EmbreeAccelerator embree(scene);
        const BvhAccelerator bvh(scene);
        Ray ray;
        ray.origin = r.origin;
        ray.direction = r.direction;
        ray.tfar = r.tfar;
        ray.time = r.time;
        Hit unnamed;
        if (embree.intersect(ray, unnamed) && unnamed.geomId == left.geomId && unnamed.primId == left.primId)
            ++metAgainUnnamed;
        if (r.segment) {
            EXPECT_EQ(embree.occluded(ray, left), bvh.occluded(ray)) << "scale " << r.scale;
            continue;
        }
        Hit ours, theirs;
        const bool foundOurs = bvh.intersect(ray, ours);
        const bool foundTheirs = embree.intersect(ray, theirs, left);
        ASSERT_EQ(foundTheirs, foundOurs) << "scale " << r.scale;
        if (!foundOurs) continue;
        EXPECT_FALSE(theirs.geomId == left.geomId && theirs.primId == left.primId) << "scale " << r.scale;
        EXPECT_EQ(theirs.geomId, ours.geomId) << "scale " << r.scale;
        EXPECT_EQ(theirs.primId, ours.primId) << "scale " << r.scale;
    }
    std::printf("Embree met the triangle left again on %d of %zu rays when it was not named\n",
                metAgainUnnamed, std::size(kRays));
}

}  // namespace
}  // namespace penumbra
