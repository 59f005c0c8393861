// `penumbra crosscheck` (tools/crosscheck.h): its ray sets are deterministic, its classification
// of disagreements says what it should, and its output reproduces the rays it lists.
#include "tools/crosscheck.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

#include "accel/embree_accelerator.h"
#include "tests/support/run_command.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

bool sameBits(const Ray& a, const Ray& b) {
    return std::memcmp(&a.origin, &b.origin, sizeof(Vec3f)) == 0 &&
           std::memcmp(&a.direction, &b.direction, sizeof(Vec3f)) == 0 &&
           std::memcmp(&a.tnear, &b.tnear, 4) == 0 && std::memcmp(&a.tfar, &b.tfar, 4) == 0 &&
           std::memcmp(&a.time, &b.time, 4) == 0;
}

TEST(Crosscheck, RaySetsAreDeterministicAndSplitIntoFourKinds) {
    const Scene scene = testing::makeSmallBoxScene(32, 32, 1);
    const EmbreeAccelerator embree(scene);
    CrosscheckOptions options;
    options.rays = 4001;
    options.seed = 5;
    const auto a = generateCrosscheckRays(scene, embree, options);
    const auto b = generateCrosscheckRays(scene, embree, options);
    ASSERT_EQ(a.size(), 4001u);
    ASSERT_EQ(b.size(), a.size());
    int perKind[kCrosscheckRayKindCount] = {};
    for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_TRUE(sameBits(a[i].ray, b[i].ray)) << "ray " << i;
        EXPECT_EQ(a[i].kind, b[i].kind);
        ++perKind[size_t(a[i].kind)];
    }
    // The box is closed, so every path continues and every kind gets its quarter.
    EXPECT_EQ(perKind[size_t(CrosscheckRayKind::Camera)], 1000);
    EXPECT_EQ(perKind[size_t(CrosscheckRayKind::Bounce)], 1000);
    EXPECT_EQ(perKind[size_t(CrosscheckRayKind::Shadow)], 1000);
    EXPECT_EQ(perKind[size_t(CrosscheckRayKind::Random)], 1001);
    for (const CrosscheckRay& r : a) {
        if (r.kind == CrosscheckRayKind::Shadow) {
            EXPECT_LT(r.ray.tfar, 1.0f) << "shadow rays are segments";
        }
    }

    options.seed = 6;
    const auto c = generateCrosscheckRays(scene, embree, options);
    int differing = 0;
    for (size_t i = 0; i < a.size(); ++i) differing += sameBits(a[i].ray, c[i].ray) ? 0 : 1;
    EXPECT_GT(differing, 3900) << "another seed gives other rays";
}

// A floor quad (two triangles, z = 0) and, coplanar with it, an overlapping quad; a sphere.
class Classification : public ::testing::Test {
protected:
    void SetUp() override {
        scene.meshes.push_back(testing::makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0));
        scene.meshes.push_back(testing::makeQuad({0.25f, 0.25f, 0}, {0.5f, 0, 0}, {0, 0.5f, 0}, 0));
        Sphere s;
        s.center = {3, 0, 0};
        s.radius = 1;
        scene.spheres.push_back(s);
    }
    static CrosscheckRay ray(Vec3f origin, Vec3f direction,
                             CrosscheckRayKind kind = CrosscheckRayKind::Random) {
        CrosscheckRay r;
        r.ray.origin = origin;
        r.ray.direction = direction;
        r.kind = kind;
        if (kind == CrosscheckRayKind::Shadow) r.ray.tfar = 1.0f - 0x1p-20f;
        return r;
    }
    static BackendAnswer hit(uint32_t geomId, uint32_t primId, float t, float u = 0.3f, float v = 0.3f) {
        BackendAnswer a;
        a.hitSomething = a.hasHit = true;
        a.hit.geomId = geomId;
        a.hit.primId = primId;
        a.hit.t = t;
        a.hit.u = u;
        a.hit.v = v;
        return a;
    }
    Scene scene;
};

TEST_F(Classification, NamesTheExpectedReasons) {
    const MismatchClassifier classifier(scene);
    const BackendAnswer miss;
    const CrosscheckRay down = ray({0.5f, 0.5f, 1}, {0, 0, -1});
    // A hit on the diagonal that the other backend missed.
    EXPECT_EQ(classifier.classify(down, hit(0, 0, 1.0f, 0.5f, 0.5f - 1e-7f), miss),
              MismatchKind::EdgeOrVertex);
    EXPECT_EQ(classifier.classify(down, miss, hit(0, 1, 1.0f, 0.0f, 0.5f)), MismatchKind::EdgeOrVertex);
    // Two coplanar quads at the same distance.
    EXPECT_EQ(classifier.classify(down, hit(0, 0, 1.0f), hit(1, 1, 1.0f)), MismatchKind::Tie);
    // Grazing the floor.
    const CrosscheckRay grazing = ray({-1, 0.5f, 1e-5f}, {1, 0, -1e-5f});
    EXPECT_EQ(classifier.classify(grazing, hit(0, 0, 1.0f), miss), MismatchKind::Grazing);
    // Tangent to the sphere.
    const CrosscheckRay tangent = ray({3, -5, 1}, {0, 1, 0});
    EXPECT_EQ(classifier.classify(tangent, miss, hit(2, 0, 5.0f, 0, 0)), MismatchKind::Grazing);
    // A shadow segment blocked right at its end.
    CrosscheckRay segment = ray({0.5f, 0.5f, 1}, {0, 0, -1}, CrosscheckRayKind::Shadow);
    EXPECT_EQ(classifier.classify(segment, hit(0, 0, segment.ray.tfar), BackendAnswer{}),
              MismatchKind::RangeBoundary);
    // A plain interior hit that the other backend missed is a bug.
    EXPECT_EQ(classifier.classify(down, hit(0, 0, 1.0f), miss), MismatchKind::Unexplained);
    // So is a nearer interior hit one backend skipped for a farther one.
    const CrosscheckRay fromAbove = ray({3, 0, 5}, {0, 0, -1});
    EXPECT_EQ(classifier.classify(fromAbove, hit(2, 0, 4.0f, 0, 0), hit(0, 0, 5.0f)),
              MismatchKind::Unexplained);
    // And a segment said to be blocked where intersect() finds nothing.
    BackendAnswer blockedWithoutHit;
    blockedWithoutHit.hitSomething = true;
    EXPECT_EQ(classifier.classify(segment, blockedWithoutHit, BackendAnswer{}), MismatchKind::Unexplained);
}

// A ray leaving the floor that one backend finds on the triangle it leaves is a self-intersection,
// a failure; a hit our triangle test rejects as within its error of the origin, or a shadow
// segment blocked at its far end, are range boundaries.
TEST_F(Classification, NamesSelfIntersections) {
    const MismatchClassifier classifier(scene);
    const BackendAnswer miss;
    CrosscheckRay bounce = ray({0.5f, 0.5f, 1e-7f}, {0.6f, 0, 0.8f}, CrosscheckRayKind::Bounce);
    bounce.leavesSurface = true;
    bounce.sourceGeomId = 0;
    bounce.sourcePrimId = 1;
    bounce.sourceDistance = 2e-7f;
    EXPECT_EQ(classifier.classify(bounce, hit(0, 1, 1e-6f), miss), MismatchKind::SelfIntersection);
    EXPECT_EQ(classifier.classify(bounce, miss, hit(0, 1, 1e-6f)), MismatchKind::SelfIntersection);
    const CrosscheckRay up = ray({0.6f, 0.6f, -1e-9f}, {0, 0, 1});
    EXPECT_EQ(classifier.classify(up, miss, hit(0, 1, 1e-9f)), MismatchKind::RangeBoundary);
    // Leaving the sphere inwards, its far side is a genuine hit.
    CrosscheckRay inwards = ray({2.0f + 1e-6f, 0, 0}, {1, 0, 0}, CrosscheckRayKind::Bounce);
    inwards.leavesSurface = true;
    inwards.sourceGeomId = 2;
    inwards.sourceDistance = 2e-6f;
    EXPECT_NE(classifier.classify(inwards, hit(2, 0, 2.0f, 0, 0), miss), MismatchKind::SelfIntersection);
    CrosscheckRay segment = ray({0.5f, 0.5f, 1}, {0, 0, -1}, CrosscheckRayKind::Shadow);
    segment.leavesSurface = true;
    segment.sourceGeomId = 2;
    segment.sourceDistance = 1e-6f;
    EXPECT_EQ(classifier.classify(segment, hit(0, 0, segment.ray.tfar), BackendAnswer{}),
              MismatchKind::RangeBoundary);
    CrosscheckReport report;
    report.mismatchesByKind[size_t(MismatchKind::SelfIntersection)] = 1;
    EXPECT_EQ(report.failures(), 1u);
}

// A shadow ray towards a light on the floor's horizon may start above the floor and point a hair
// below it (the side is chosen from the direction at the hit point, the direction taken from the
// moved origin): meeting the triangle it leaves is then a grazing hit (both answers are within
// rounding), as Embree's hits on the Cornell box's boxes at cos ~ 1e-7 were. Crossing the plane
// at a larger angle is a ray sent to the wrong side: still a self-intersection.
TEST_F(Classification, ARayBackThroughItsTriangleAtAGlanceIsGrazing) {
    const MismatchClassifier classifier(scene);
    const BackendAnswer miss;
    CrosscheckRay horizon = ray({0.5f, 0.5f, 1e-7f}, {1, 0, -2e-7f}, CrosscheckRayKind::Shadow);
    horizon.leavesSurface = true;
    horizon.sourceGeomId = 0;
    horizon.sourcePrimId = 1;
    horizon.sourceDistance = 2e-7f;
    EXPECT_EQ(classifier.classify(horizon, miss, hit(0, 1, 0.5f)), MismatchKind::Grazing);
    // Leaving at a glancing angle without crossing the plane: a hit on its triangle is impossible.
    CrosscheckRay above = horizon;
    above.ray.direction = {1, 0, 2e-7f};
    EXPECT_EQ(classifier.classify(above, miss, hit(0, 1, 0.5f)), MismatchKind::SelfIntersection);
    CrosscheckRay steep = horizon;
    steep.ray.direction = {0.6f, 0, -0.8f};
    EXPECT_EQ(classifier.classify(steep, miss, hit(0, 1, 1.25e-7f)), MismatchKind::SelfIntersection);
}

TEST(Crosscheck, BoxSceneAgreesAndReportsFigures) {
    CrosscheckOptions options;
    options.rays = 20000;
    const CrosscheckReport report = runCrosscheck(testing::makeSmallBoxScene(32, 32, 1), options);
    EXPECT_EQ(report.rayCount, 20000u);
    EXPECT_EQ(report.unexplained(), 0u);
    EXPECT_GT(report.agreementRatio(), 0.999);
    EXPECT_GT(report.samePrimitiveHits, 10000u);
    EXPECT_GT(report.oursRaysPerSecond, 0.0);
    EXPECT_GT(report.embreeRaysPerSecond, 0.0);

    const nlohmann::json j = nlohmann::json::parse(formatCrosscheckJson(report));
    EXPECT_EQ(j["rays"], 20000);
    EXPECT_EQ(j["unexplained"], 0);
    EXPECT_TRUE(j["throughput"].contains("ratio"));
    EXPECT_TRUE(j["byKind"].contains("shadow"));
    EXPECT_NE(formatCrosscheckText(report).find("agreement"), std::string::npos);
}

TEST(Crosscheck, ListedRaysReproduceBitForBit) {
    CrosscheckReport report;
    report.rayCount = 1;
    Mismatch m;
    m.ray.ray.origin = {0.1f, -1.0f / 3.0f, 1e-30f};
    m.ray.ray.direction = {std::nextafter(1.0f, 2.0f), -0.0f, 7.0f};
    m.ray.ray.tfar = 1.0f - 0x1p-20f;
    m.ray.kind = CrosscheckRayKind::Shadow;
    m.ours.hitSomething = true;
    report.mismatches.push_back(m);
    report.mismatchesByKind[size_t(MismatchKind::Unexplained)] = 1;
    const nlohmann::json j = nlohmann::json::parse(formatCrosscheckJson(report));
    const auto& listed = j["listedMismatches"].at(0);
    EXPECT_EQ(listed["call"], "occluded");
    auto parse = [](const nlohmann::json& text) {
        return std::strtof(text.get<std::string>().c_str(), nullptr);
    };
    Ray back;
    back.origin = {parse(listed["origin"][0]), parse(listed["origin"][1]), parse(listed["origin"][2])};
    back.direction = {parse(listed["direction"][0]), parse(listed["direction"][1]),
                      parse(listed["direction"][2])};
    back.tnear = parse(listed["tnear"]);
    back.tfar = parse(listed["tfar"]);
    back.time = parse(listed["time"]);
    EXPECT_TRUE(sameBits(back, m.ray.ray));
    const std::string text = formatCrosscheckText(report);
    EXPECT_NE(text.find("0x1.000002p+0"), std::string::npos) << text;
    EXPECT_NE(text.find("[unexplained] shadow ray"), std::string::npos) << text;
}

// The subcommand end to end, on the example Cornell box (which has coplanar boxes on its floor:
// ties, explained).
TEST(Crosscheck, CommandLine) {
    const testing::RunResult run =
        testing::runPenumbra(std::string("crosscheck ") + PENUMBRA_SOURCE_DIR +
                             "/scenes/cornell-box.json --rays 20000 --seed 3 --json");
    ASSERT_NE(run.exitCode, -1) << "did not run or exit normally";
    EXPECT_EQ(run.exitCode, 0) << run.output;
    const std::string& output = run.output;
    const nlohmann::json j = nlohmann::json::parse(output);
    EXPECT_EQ(j["rays"], 20000);
    EXPECT_EQ(j["seed"], 3);
    EXPECT_EQ(j["unexplained"], 0);
}

}  // namespace
}  // namespace penumbra
