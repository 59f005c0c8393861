// Instancing (SceneGeometry::prototypes and instances) in both backends: they find the same
// primitives and, after canonicalisation, the same shading points bit for bit; the crosscheck
// explains every disagreement; instances render the image of the same meshes copied into the
// scene; a moving instance is traced bit for bit as the same mesh given as a moving shape (both in
// object space through the same transform); and a thousand instances of a large mesh cost next
// to nothing in memory.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "core/hash.h"
#include "core/sampling.h"
#include "film/film.h"
#include "geometry/face_frames.h"
#include "geometry/surface_interaction.h"
#include "renderer/render.h"
#include "scenes/mesh_import.h"
#include "tests/support/film_comparison.h"
#include "tests/support/render_scene.h"
#include "tests/support/scene_builders.h"
#include "tools/crosscheck.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::renderScene;

float uniform(uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(0x1257, index, dimension) >> 32));
}

// A closed, lumpy ball of radius about 1: a UV sphere whose radius varies with the direction,
// so that its triangles face every way and differ in size.
TriangleMesh makeLumpyBall(int rings, int segments) {
    TriangleMesh mesh;
    mesh.name = "lumpy ball";
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i < segments; ++i) {
            const float theta = kPi * float(j) / float(rings), phi = 2.0f * kPi * float(i) / float(segments);
            const float r = 1.0f + 0.15f * std::sin(3.0f * phi) * std::sin(2.0f * theta);
            mesh.positions.push_back({r * std::sin(theta) * std::cos(phi), r * std::cos(theta),
                                      r * std::sin(theta) * std::sin(phi)});
            if (j == 0 || j == rings) break;  // one vertex at each pole
        }
    auto vertex = [&](int j, int i) -> uint32_t {
        if (j == 0) return 0;
        if (j == rings) return uint32_t(1 + (rings - 1) * segments);
        return uint32_t(1 + (j - 1) * segments + (i % segments));
    };
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < segments; ++i) {
            // Counter-clockwise seen from outside.
            const uint32_t a = vertex(j, i), b = vertex(j, i + 1), c = vertex(j + 1, i),
                           d = vertex(j + 1, i + 1);
            if (j != 0) mesh.indices.insert(mesh.indices.end(), {a, b, c});
            if (j != rings - 1) mesh.indices.insert(mesh.indices.end(), {b, d, c});
        }
    return mesh;
}

// Placements: rotated, scaled unevenly, mirrored, sheared, at different distances.
std::vector<Transform> stillPlacements() {
    Matrix4 shear = Matrix4::identity();
    shear.m[0][1] = 0.4f;
    return {
        Transform::translate({-1.6f, 0.9f, 0.0f}) * Transform::rotate(30.0f, {0, 1, 0}) *
            Transform::scale({0.8f, 0.8f, 0.8f}),
        Transform::translate({0.9f, 0.7f, -0.5f}) * Transform::rotate(-50.0f, {1, 1, 0}) *
            Transform::scale({1.0f, 0.6f, 0.7f}),
        Transform::translate({0.2f, 0.5f, 1.4f}) * Transform::scale({0.5f, -0.5f, 0.5f}),  // mirrored
        Transform::translate({2.2f, 1.0f, 1.0f}) * *Transform::fromMatrix(shear) *
            Transform::scale({0.6f, 0.9f, 0.6f}),
        Transform::translate({-0.4f, 2.4f, -2.0f}) * Transform::rotate(75.0f, {0, 0, 1}),
    };
}

// Lit by one ceiling quad over a floor; black background, so that nothing depends on the scene's
// bounds (the light set's background estimate).
Scene makeBase() {
    Scene scene;
    scene.film.width = 64;
    scene.film.height = 48;
    scene.film.samplesPerPixel = 8;
    scene.camera.lookFrom = {0.0f, 2.5f, 6.5f};
    scene.camera.lookAt = {0.0f, 0.8f, 0.0f};
    scene.camera.verticalFovDegrees = 45.0f;
    scene.camera.shutterOpen = 0.0f;
    scene.camera.shutterClose = 1.0f;
    scene.materials = {testing::makeLambert(Rgb(0.6f)), testing::makeLambert({0.7f, 0.2f, 0.1f}),
                       testing::makeLambert({0.1f, 0.3f, 0.7f}), testing::makeLambert(Rgb(0.0f))};
    scene.meshes.push_back(testing::makeQuad({-6, 0, -6}, {0, 0, 12}, {12, 0, 0}, 0));  // floor, +y
    TriangleMesh light = testing::makeQuad({-1, 4, -1}, {2, 0, 0}, {0, 0, 2}, 3);       // faces -y
    light.emission.radiance = Rgb(6.0f);
    scene.meshes.push_back(light);
    return scene;
}

Scene makeInstancedScene() {
    Scene scene = makeBase();
    scene.prototypes.push_back(makeLumpyBall(24, 48));
    const std::vector<Transform> placements = stillPlacements();
    for (size_t k = 0; k < placements.size(); ++k) {
        MeshInstance instance;
        instance.name = "instance " + std::to_string(k);
        instance.placement = placements[k];
        instance.material = uint32_t(k % 3);
        scene.instances.push_back(instance);
    }
    return scene;
}

// The same scene with each instance's mesh copied and transformed into the world.
Scene copyInstances(const Scene& instanced) {
    Scene scene = instanced;
    scene.prototypes.clear();
    scene.instances.clear();
    for (const MeshInstance& instance : instanced.instances) {
        TriangleMesh mesh = instanced.prototypes[instance.prototype];
        transformMesh(mesh, instance.placement);
        mesh.material = instance.material;
        scene.meshes.push_back(mesh);
    }
    return scene;
}

// Rays from random points around the scene towards random points on or near the instances.
Ray randomRay(uint64_t i) {
    Ray ray;
    ray.origin = {-5.0f + 10.0f * uniform(i, 0), 0.2f + 5.0f * uniform(i, 1), -5.0f + 10.0f * uniform(i, 2)};
    const Vec3f target{-2.5f + 5.0f * uniform(i, 3), 0.0f + 3.0f * uniform(i, 4),
                       -2.5f + 5.0f * uniform(i, 5)};
    ray.direction = target - ray.origin;
    ray.time = uniform(i, 6);
    return ray;
}

bool sameBits(const void* a, const void* b, size_t n) { return std::memcmp(a, b, n) == 0; }

void expectSameInteraction(const SurfaceInteraction& a, const SurfaceInteraction& b, uint64_t ray) {
    EXPECT_TRUE(sameBits(&a.position, &b.position, sizeof(Vec3f))) << "ray " << ray;
    EXPECT_TRUE(sameBits(&a.positionError, &b.positionError, sizeof(Vec3f))) << "ray " << ray;
    EXPECT_TRUE(sameBits(&a.geometricNormal, &b.geometricNormal, sizeof(Vec3f))) << "ray " << ray;
    EXPECT_TRUE(sameBits(&a.shadingNormal, &b.shadingNormal, sizeof(Vec3f))) << "ray " << ray;
    EXPECT_EQ(a.material, b.material) << "ray " << ray;
}

// Both backends on the same rays: wherever they report the same (instance, triangle), Embree's hit
// recomputed in the instance's object space gives our BVH's t, barycentrics and shading point bit
// for bit; and the shading point with the prototype's face frames is the one computed without.
void checkBackendsAgree(const Scene& scene, int rays) {
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    const FaceFrames frames(scene);
    int same = 0, instanceHits = 0, differ = 0;
    for (int i = 0; i < rays; ++i) {
        const Ray ray = randomRay(uint64_t(i));
        Hit a, b;
        const bool foundA = bvh.intersect(ray, a), foundB = embree.intersect(ray, b);
        if (foundA != foundB || (foundA && (a.geomId != b.geomId || a.primId != b.primId))) {
            ++differ;
            continue;
        }
        if (!foundA) continue;
        ++same;
        instanceHits += scene.shapeOf(a).kind == ShapeKind::Instance;
        Hit ours = a, theirs = b;
        const SurfaceInteraction siA = resolveHit<true>(scene, ray, ours, &frames);
        const SurfaceInteraction siB = resolveHit<false>(scene, ray, theirs, &frames);
        ASSERT_TRUE(sameBits(&ours.t, &theirs.t, 4) && sameBits(&ours.u, &theirs.u, 4) &&
                    sameBits(&ours.v, &theirs.v, 4))
            << "ray " << i << ": t " << ours.t << " vs " << theirs.t;
        expectSameInteraction(siA, siB, uint64_t(i));
        expectSameInteraction(siA, makeSurfaceInteraction(scene, ray, a), uint64_t(i));
    }
    std::printf("%d rays: %d on the same primitive (%d on instances), %d differ\n", rays, same, instanceHits,
                differ);
    EXPECT_GT(instanceHits, rays / 10);
    EXPECT_LE(differ, rays / 10000 + 2);  // rays along edges and ties only
}

TEST(InstancingBackends, SameHitsAndShadingPointsBitForBit) {
    checkBackendsAgree(makeInstancedScene(), 100000);
}

// Moving instances: translation, rotation and scale keys.
Scene makeMovingScene() {
    Scene scene = makeInstancedScene();
    MeshInstance moving;
    moving.name = "moving";
    TransformKey a, b, c;
    a.translation = {-1.0f, 0.8f, 1.5f};
    b.translation = {0.0f, 1.0f, 1.8f};
    b.rotation = Quaternion::fromAxisAngle({0, 1, 0.3f}, 60.0f);
    b.scale = {0.7f, 0.7f, 0.7f};
    c.translation = {1.0f, 0.8f, 1.5f};
    c.rotation = Quaternion::fromAxisAngle({0, 1, 0.3f}, 120.0f);
    c.scale = {0.5f, 0.6f, 0.5f};
    moving.motion.keys = {a, b, c};
    moving.material = 1;
    scene.instances.push_back(moving);
    return scene;
}

TEST(InstancingBackends, MovingInstancesSameHitsAndShadingPointsBitForBit) {
    checkBackendsAgree(makeMovingScene(), 100000);
}

TEST(InstancingBackends, CrosscheckExplainsEveryMismatch) {
    Scene scene = makeMovingScene();
    scene.sourcePath = "instanced";
    const EmbreeAccelerator embree(scene);
    const BvhAccelerator bvh(scene);
    CrosscheckOptions options;
    options.rays = 200000;
    options.measureThroughput = false;
    const std::vector<CrosscheckRay> rays = generateCrosscheckRays(scene, embree, options);
    const CrosscheckReport report = compareBackends(scene, bvh, embree, rays, options);
    EXPECT_EQ(report.unexplained(), 0u);
    // Rays leaving an instance start far enough from it in its own space too
    // (placeInWorld's bound on the way back into object space), whichever backend transforms them.
    EXPECT_EQ(report.selfIntersections(), 0u);
    EXPECT_GT(report.agreementRatio(), 0.9999);
}

// Instances against copies: the same geometry, computed in another space, so hit points differ in
// the last bits and paths diverge slowly; every pixel must agree within its noise, and so must
// the image's mean.
TEST(InstancingRender, InstancesRenderLikeTheMeshesCopied) {
    const Scene instanced = makeInstancedScene();
    const Scene copied = copyInstances(instanced);
    const Film a = renderScene(instanced), b = renderScene(copied);
    const testing::FilmComparison c = testing::compareWithinNoise(a, b);
    std::printf("means: instanced %.6f, copied %.6f; %d identical pixels\n", c.meanA, c.meanB,
                c.identicalPixels);
    EXPECT_EQ(c.outlierChannels, 0);
    EXPECT_NEAR(c.meanA, c.meanB, 0.01 * c.meanB);
    EXPECT_GT(c.meanA, 0.01);
}

// Where both backends find the same primitives the images are the same bits; a path that meets a
// different primitive (a ray along an edge) changes its pixel, which is rare (see
// ExampleScenes.BothBackendsRenderTheSameImages for the rate).
TEST(InstancingRender, BothBackendsRenderTheSameImage) {
    for (const Scene& scene : {makeInstancedScene(), makeMovingScene()}) {
        const Film embree = renderScene(scene), bvh = renderScene(scene, 2, AcceleratorKind::Bvh);
        const testing::FilmComparison c = testing::compareWithinNoise(embree, bvh);
        EXPECT_GE(c.identicalPixels, 64 * 48 - 3);
        EXPECT_EQ(c.outlierChannels, 0);
    }
}

// A moving instance is traced exactly as the same mesh given as a moving shape (both in object
// space through motion.at(time)): each backend finds the same triangle at the same t and
// barycentrics, bit for bit. Shading differs only in the instance's wider error bound
// (placeInWorld's bound on the way back into object space), so the images agree within noise.
TEST(InstancingRender, MovingInstanceTracesLikeTheMovingMesh) {
    Scene instanced = makeBase();
    instanced.prototypes.push_back(makeLumpyBall(24, 48));
    MeshInstance moving;
    TransformKey a, b;
    a.translation = {-1.0f, 1.0f, 0.0f};
    b.translation = {1.0f, 1.2f, 0.0f};
    b.rotation = Quaternion::fromAxisAngle({0, 1, 0}, 90.0f);
    b.scale = {0.8f, 1.1f, 0.8f};
    moving.motion.keys = {a, b};
    moving.material = 1;
    instanced.instances.push_back(moving);
    Scene shape = makeBase();
    TriangleMesh mesh = instanced.prototypes[0];
    mesh.motion = moving.motion;
    mesh.material = 1;
    shape.meshes.push_back(mesh);

    const BvhAccelerator bvhA(instanced), bvhB(shape);
    const EmbreeAccelerator embreeA(instanced), embreeB(shape);
    int onTheMesh = 0;
    for (int i = 0; i < 50000; ++i) {
        const Ray ray = randomRay(uint64_t(i));
        Hit x, y, u, v;
        const bool fx = bvhA.intersect(ray, x), fy = bvhB.intersect(ray, y);
        const bool fu = embreeA.intersect(ray, u), fv = embreeB.intersect(ray, v);
        ASSERT_EQ(fx, fy) << "ray " << i;
        ASSERT_EQ(fu, fv) << "ray " << i;
        if (fx) {
            const bool onInstance = instanced.shapeOf(x).kind == ShapeKind::Instance;
            ASSERT_EQ(onInstance, y.geomId == 2u) << "ray " << i;  // the moving mesh follows floor and light
            if (onInstance) {
                ++onTheMesh;
                EXPECT_EQ(x.primId, y.primId) << "ray " << i;
                EXPECT_TRUE(sameBits(&x.t, &y.t, 4) && sameBits(&x.u, &y.u, 4) && sameBits(&x.v, &y.v, 4))
                    << "ray " << i;
            }
        }
        if (fu && instanced.shapeOf(u).kind == ShapeKind::Instance) {
            Hit cu = u, cv = v;
            canonicalizeHit(instanced, ray, cu);
            canonicalizeHit(shape, ray, cv);
            EXPECT_EQ(u.primId, v.primId) << "ray " << i;
            EXPECT_TRUE(sameBits(&cu.t, &cv.t, 4) && sameBits(&cu.u, &cv.u, 4) && sameBits(&cu.v, &cv.v, 4))
                << "ray " << i;
        }
    }
    EXPECT_GT(onTheMesh, 1000);
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        const Film x = renderScene(instanced, 2, accelerator), y = renderScene(shape, 2, accelerator);
        const testing::FilmComparison c = testing::compareWithinNoise(x, y);
        EXPECT_EQ(c.outlierChannels, 0) << acceleratorKindName(accelerator);
        EXPECT_NEAR(c.meanA, c.meanB, 0.01 * c.meanB) << acceleratorKindName(accelerator);
        EXPECT_GT(c.meanA, 0.01);
    }
}

// Peak resident memory of `penumbra render SCENE` in kilobytes (the child's getrusage), or -1.
long peakKilobytesOfRender(const fs::path& scene, const char* accel) {
    const pid_t pid = fork();
    if (pid == 0) {
        const int null = open("/dev/null", O_WRONLY);
        dup2(null, 1);
        dup2(null, 2);
        const std::string output =
            (fs::temp_directory_path() / ("penumbra_instancing_" + std::to_string(getpid()) + ".exr"))
                .string();
        execl(PENUMBRA_BINARY, PENUMBRA_BINARY, "render", scene.c_str(), "--accel", accel, "--threads", "2",
              "-q", "--no-display", "-o", output.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    int status = 0;
    rusage usage{};
    if (pid < 0 || wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1;
    return usage.ru_maxrss;
}

// A scene of `count` instances of the 871k-triangle Stanford dragon on a grid, each turned and
// given one of three materials, over a floor.
fs::path writeDragonScene(const fs::path& dragon, int count) {
    const fs::path path = fs::temp_directory_path() / ("penumbra_dragons_" + std::to_string(count) + "_" +
                                                       std::to_string(getpid()) + ".json");
    std::ofstream out(path);
    out << R"({"camera": {"look_from": [0, 4, 8], "look_at": [0, 0, -6], "fov": 50},
        "film": {"resolution": [64, 48], "spp": 1}, "background": 0.5,
        "materials": {"a": {"type": "lambert"}, "b": {"type": "lambert", "albedo": [0.7, 0.2, 0.2]},
                      "c": {"type": "lambert", "albedo": [0.2, 0.2, 0.7]}},
        "prototypes": {"dragon": {"type": "mesh_file", "file": )"
        << nlohmann::json(dragon.string()).dump() << R"(}},
        "shapes": [{"type": "quad", "corner": [-30, -0.2, 10], "edge1": [60, 0, 0], "edge2": [0, 0, -60], "material": "a"})";
    for (int i = 0; i < count; ++i)
        out << R"(, {"type": "instance", "prototype": "dragon", "material": ")"
            << "abc"[i % 3] << R"(", "transform": [{"scale": 3}, {"rotate": {"axis": [0, 1, 0], "degrees": )"
            << (i * 37) % 360 << R"(}}, {"translate": [)" << 0.6 * (i % 32 - 16) << ", 0, " << -0.6 * (i / 32)
            << "]}]}";
    out << "]}\n";
    return path;
}

// 1000 instances of the dragon against one: the prototype is stored and built once, so the peak
// memory of the whole render grows by the instances' own few hundred bytes each. The ratio is
// deterministic up to allocator noise of a few megabytes (of about 200 MB).
TEST(InstancingMemory, ThousandDragonsCostLessThanOneAndAFifthDragons) {
    const fs::path dragon = fs::path(PENUMBRA_DATA_DIR) / "meshes" / "dragon_vrip.ply.gz";
    if (!fs::exists(dragon)) GTEST_SKIP() << "no " << dragon;
    const fs::path one = writeDragonScene(dragon, 1), thousand = writeDragonScene(dragon, 1000);
    for (const char* accel : {"embree", "bvh"}) {
        const long a = peakKilobytesOfRender(one, accel), b = peakKilobytesOfRender(thousand, accel);
        ASSERT_GT(a, 0) << accel;
        ASSERT_GT(b, 0) << accel;
        std::printf("%s: peak RSS one dragon %ld kB, 1000 dragons %ld kB, ratio %.3f\n", accel, a, b,
                    double(b) / double(a));
        EXPECT_LT(double(b), 1.2 * double(a)) << accel;
    }
    fs::remove(one);
    fs::remove(thousand);
}

}  // namespace
}  // namespace penumbra
