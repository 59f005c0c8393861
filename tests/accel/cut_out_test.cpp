// Cut-outs (geometry/cut_out.h) in both backends: the stochastic test keeps a hit with
// probability alpha, independently for two surfaces; a constant alpha makes both backends decide
// alike ray by ray, on still, moving, deforming and instanced meshes, for intersect, occluded and
// Embree's packets; a checkerboard alpha lets rays through exactly where it is 0; the crosscheck
// explains every disagreement; and an emitter with a cut-out lights a scene as its coverage says.
#include "geometry/cut_out.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "core/hash.h"
#include "film/film.h"
#include "lights/triangle_light.h"
#include "renderer/render.h"
#include "tests/support/render_scene.h"
#include "tests/support/scene_builders.h"
#include "tools/crosscheck.h"

namespace penumbra {
namespace {

using testing::renderScene;

float uniform(uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(0xc07, index, dimension) >> 32));
}

// Five standard deviations of a fraction of n Bernoulli(p) trials.
double fiveSigma(double p, double n) { return 5.0 * std::sqrt(p * (1.0 - p) / n); }

TEST(CutOutTest, KeepsAHitWithProbabilityAlphaIndependentlyPerTriangle) {
    constexpr int kRays = 1'000'000;
    for (float alpha : {0.1f, 0.3f, 0.7f}) {
        int kept = 0, keptBoth = 0;
        for (int i = 0; i < kRays; ++i) {
            const uint64_t ray = hashWords(7, uint64_t(i));
            const bool a = keepsCutOutHit(alpha, ray, 3, 10), b = keepsCutOutHit(alpha, ray, 3, 11);
            kept += a;
            keptBoth += a && b;
        }
        EXPECT_NEAR(double(kept) / kRays, alpha, fiveSigma(alpha, kRays)) << alpha;
        // Two triangles on one ray decide independently: both kept alpha^2 of the time.
        const double both = double(alpha) * alpha;
        EXPECT_NEAR(double(keptBoth) / kRays, both, fiveSigma(both, kRays)) << alpha;
    }
    for (int i = 0; i < 1000; ++i) {
        EXPECT_TRUE(keepsCutOutHit(1.0f, uint64_t(i), 0, 0));
        EXPECT_TRUE(keepsCutOutHit(2.0f, uint64_t(i), 0, 0));
        EXPECT_FALSE(keepsCutOutHit(0.0f, uint64_t(i), 0, 0));
        EXPECT_FALSE(keepsCutOutHit(-1.0f, uint64_t(i), 0, 0));
        EXPECT_FALSE(keepsCutOutHit(std::nanf(""), uint64_t(i), 0, 0));
    }
}

// A cut-out quad over z = 0 (x, y in [-1, 1], uvs from its corners) above an opaque floor at z = -1.
enum class QuadKind { Still, Moving, Deforming, Instance };

TriangleMesh uvQuad(float z) {
    TriangleMesh quad = testing::makeQuad({-1, -1, z}, {2, 0, 0}, {0, 2, 0}, 0);
    quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    return quad;
}

Scene cutOutScene(QuadKind kind, const Texture& alpha) {
    Scene scene;
    scene.materials.push_back(testing::makeLambert(Rgb(0.5f)));
    scene.meshes.push_back(testing::makeQuad({-2, -2, -1}, {4, 0, 0}, {0, 4, 0}, 0));  // the floor, id 0
    TriangleMesh quad = uvQuad(0.0f);
    quad.alpha = std::make_shared<const Texture>(alpha);
    if (kind == QuadKind::Moving) quad.motion.keys = {TransformKey{}, TransformKey{}};
    if (kind == QuadKind::Deforming) quad.positionKeys = {quad.positions, quad.positions};
    if (kind == QuadKind::Instance) {
        scene.prototypes.push_back(quad);
        MeshInstance instance;
        instance.prototype = 0;
        instance.placement = Transform::translate({0, 0, 0});
        scene.instances.push_back(instance);
    } else {
        scene.meshes.push_back(quad);  // id 1
    }
    return scene;
}

uint32_t quadGeomId(const Scene& scene) { return scene.instances.empty() ? 1u : scene.instanceGeomId(0); }

// A ray down from z = 1 through (x, y) in the quad, slightly tilted.
Ray downRay(int i) {
    Ray ray;
    ray.origin = {2.0f * uniform(i, 0) - 1.0f, 2.0f * uniform(i, 1) - 1.0f, 1.0f};
    ray.direction = {0.01f * (uniform(i, 2) - 0.5f), 0.01f * (uniform(i, 3) - 0.5f), -1.0f};
    ray.time = uniform(i, 4);
    return ray;
}

const char* kindName(QuadKind kind) {
    switch (kind) {
        case QuadKind::Still:
            return "still";
        case QuadKind::Moving:
            return "moving";
        case QuadKind::Deforming:
            return "deforming";
        case QuadKind::Instance:
            break;
    }
    return "instance";
}

TEST(CutOutTest, ConstantAlphaDecidesAlikeInBothBackendsForEveryKindOfMesh) {
    constexpr int kRays = 40'000;
    constexpr float kAlpha = 0.3f;
    for (QuadKind kind : {QuadKind::Still, QuadKind::Moving, QuadKind::Deforming, QuadKind::Instance}) {
        const Scene scene = cutOutScene(kind, Texture::constant(Rgb(kAlpha)));
        const BvhAccelerator bvh(scene);
        const EmbreeAccelerator embree(scene);
        const uint32_t quad = quadGeomId(scene);
        int onQuad = 0, disagreements = 0, inconsistent = 0;
        for (int i = 0; i < kRays; ++i) {
            Ray ray = downRay(i);
            Hit a, b;
            const bool foundA = bvh.intersect(ray, a), foundB = embree.intersect(ray, b);
            ASSERT_TRUE(foundA && foundB) << "the floor is under every ray";
            onQuad += a.geomId == quad;
            disagreements += a.geomId != b.geomId;
            // A segment to just above the floor is blocked exactly when the ray's closest hit is
            // the quad: the same ray, the same number.
            ray.tfar = 1.5f;
            inconsistent += bvh.occluded(ray) != (a.geomId == quad);
            inconsistent += embree.occluded(ray) != (b.geomId == quad);
        }
        std::printf("%s: %d of %d rays kept by the quad (alpha %.1f), %d disagreements\n", kindName(kind),
                    onQuad, kRays, kAlpha, disagreements);
        EXPECT_NEAR(double(onQuad) / kRays, kAlpha, fiveSigma(kAlpha, kRays)) << kindName(kind);
        EXPECT_EQ(disagreements, 0) << kindName(kind);
        EXPECT_EQ(inconsistent, 0) << kindName(kind);
    }
}

TEST(CutOutTest, EmbreePacketsDecideAsSingleRays) {
    const Scene scene = cutOutScene(QuadKind::Still, Texture::constant(Rgb(0.5f)));
    const EmbreeAccelerator embree(scene);
    int onQuad = 0;
    for (int packet = 0; packet < 500; ++packet) {
        Ray rays[EmbreeAccelerator::kPacketSize];
        Hit hits[EmbreeAccelerator::kPacketSize];
        bool found[EmbreeAccelerator::kPacketSize];
        for (int i = 0; i < EmbreeAccelerator::kPacketSize; ++i)
            rays[i] = downRay(packet * EmbreeAccelerator::kPacketSize + i);
        embree.intersectPacket(rays, EmbreeAccelerator::kPacketSize, hits, found);
        for (int i = 0; i < EmbreeAccelerator::kPacketSize; ++i) {
            Hit single;
            ASSERT_TRUE(found[i] && embree.intersect(rays[i], single));
            EXPECT_EQ(hits[i].geomId, single.geomId);
            onQuad += single.geomId == 1;
        }
    }
    EXPECT_GT(onQuad, 1000);  // of 4000: both outcomes occur
    EXPECT_LT(onQuad, 3000);
}

// A checkerboard of 4 x 4 squares, covered (1) where floor(4u) + floor(4v) is even: a ray through a
// covered square hits the quad, one through an uncovered square the floor, in both backends (rays
// within 1e-3 of a square's edge in (u, v) are left out, where the two may see either side).
TEST(CutOutTest, CheckerboardAlphaLetsRaysThroughExactlyWhereItIsZero) {
    for (QuadKind kind : {QuadKind::Still, QuadKind::Instance}) {
        const Scene scene =
            cutOutScene(kind, Texture::checkerboard(Rgb(1.0f), Rgb(0.0f)).mapUv({4.0f, 4.0f}, {0.0f, 0.0f}));
        const BvhAccelerator bvh(scene);
        const EmbreeAccelerator embree(scene);
        const uint32_t quad = quadGeomId(scene);
        int tested = 0;
        for (int i = 0; i < 20'000; ++i) {
            const Ray ray = downRay(i);
            const Vec3f p = ray.at(1.0f / -ray.direction.z);  // where it crosses z = 0
            const float u = 4.0f * (p.x + 1.0f) / 2.0f, v = 4.0f * (p.y + 1.0f) / 2.0f;
            if (!(u > 0.0f && u < 4.0f && v > 0.0f && v < 4.0f)) continue;
            if (std::abs(u - std::round(u)) < 4e-3f || std::abs(v - std::round(v)) < 4e-3f) continue;
            const bool covered = ((int(u) + int(v)) & 1) == 0;
            Hit a, b;
            ASSERT_TRUE(bvh.intersect(ray, a) && embree.intersect(ray, b));
            EXPECT_EQ(a.geomId == quad, covered) << kindName(kind) << " u " << u << " v " << v;
            EXPECT_EQ(b.geomId == quad, covered) << kindName(kind) << " u " << u << " v " << v;
            ++tested;
        }
        EXPECT_GT(tested, 15'000);
    }
}

// The crosscheck's rays (camera, bounce, shadow, random) on a scene with cut-outs of both kinds:
// every disagreement explained.
TEST(CutOutTest, CrosscheckExplainsEveryDisagreement) {
    Scene scene = cutOutScene(QuadKind::Still,
                              Texture::checkerboard(Rgb(1.0f), Rgb(0.2f)).mapUv({8.0f, 8.0f}, {0.0f, 0.0f}));
    TriangleMesh second = uvQuad(0.5f);
    second.alpha = std::make_shared<const Texture>(Texture::constant(Rgb(0.6f)));
    scene.prototypes.push_back(second);
    MeshInstance instance;
    instance.prototype = 0;
    instance.placement = Transform::rotate(20.0f, {0, 0, 1});
    scene.instances.push_back(instance);
    scene.film.width = 64;
    scene.film.height = 64;
    scene.camera.lookFrom = {0.3f, -2.5f, 2.5f};
    scene.camera.lookAt = {0.0f, 0.0f, -0.5f};
    scene.camera.up = {0.0f, 0.0f, 1.0f};
    CrosscheckOptions options;
    options.rays = 200'000;
    options.measureThroughput = false;
    const CrosscheckReport report = runCrosscheck(scene, options);
    std::printf("%s", formatCrosscheckText(report, 5).c_str());
    EXPECT_EQ(report.failures(), 0u);
    EXPECT_GT(report.agreementRatio(), 0.999);
}

// A hit that one backend kept and the other refused is explained as a cut-out edge where the
// coverage changes within a barycentric kEdgeTolerance (a checker's edge), and not elsewhere.
TEST(CutOutTest, ClassifierExplainsADisagreementAtACoverageEdgeOnly) {
    const Scene scene = cutOutScene(
        QuadKind::Still, Texture::checkerboard(Rgb(1.0f), Rgb(0.0f)).mapUv({4.0f, 4.0f}, {0.0f, 0.0f}));
    const MismatchClassifier classifier(scene);
    // Triangle 0 of the quad has uv = (b1 + b2, b2): a checker edge where b1 + b2 = 0.5.
    auto classify = [&](float b1, float b2) {
        CrosscheckRay ray;
        ray.ray.origin = {-1.0f + 2.0f * (b1 + b2), -1.0f + 2.0f * b2, 1.0f};
        ray.ray.direction = {0.0f, 0.0f, -1.0f};
        BackendAnswer kept, refused;
        kept.hitSomething = kept.hasHit = true;
        kept.hit.t = 1.0f;
        kept.hit.u = b1;
        kept.hit.v = b2;
        kept.hit.geomId = 1;
        kept.hit.primId = 0;
        return classifier.classify(ray, refused, kept);
    };
    EXPECT_EQ(classify(0.4f - 2e-6f, 0.1f), MismatchKind::CutOutEdge);
    EXPECT_EQ(classify(0.3f, 0.1f), MismatchKind::Unexplained);
}

// Next-event estimation sees a cut-out emitter's radiance times its coverage.
TEST(CutOutTest, TriangleLightSamplesRadianceTimesCoverage) {
    TriangleMesh light = uvQuad(1.0f);
    light.emission.radiance = Rgb(4.0f);
    light.emission.twoSided = true;
    light.alpha = std::make_shared<const Texture>(Texture::constant(Rgb(0.25f)));
    const TriangleLight triangle = TriangleLight::fromMesh(light, 0);
    LightSample sample;
    ASSERT_TRUE(triangle.sample({0.0f, 0.0f, 0.0f}, {0.3f, 0.4f}, sample));
    EXPECT_FLOAT_EQ(sample.radiance.r, 1.0f);
}

// A floor lit by an emitting quad of alpha 0.4 (out of view), seen from above through a cut-out
// checkerboard of coverage 1 and 0.5: the same image in expectation as an opaque emitter of 0.4 its
// radiance (the emitter lights the floor through next-event estimation and through bounces hitting it).
// Compared by the whole image's mean, whose standard error is taken from the pixels' spread.
TEST(CutOutTest, CutOutEmitterLightsAsItsCoverageSays) {
    auto scene = [](bool cutOut) {
        Scene s;
        s.film.width = 48;
        s.film.height = 48;
        s.film.samplesPerPixel = 64;
        s.camera.lookFrom = {0.0f, -0.5f, 4.0f};
        s.camera.lookAt = {0.0f, 0.0f, 0.0f};
        s.camera.up = {0.0f, 1.0f, 0.0f};
        s.materials = {testing::makeLambert(Rgb(0.6f)), testing::makeLambert(Rgb(0.0f))};
        s.meshes.push_back(testing::makeQuad({-4, -4, 0}, {8, 0, 0}, {0, 8, 0}, 0));  // floor, faces +z
        // Facing -z, out of the camera's view (which would see the floor through it).
        // Large and near the floor, so that bounces hitting it carry much of the light (MIS).
        TriangleMesh light = testing::makeQuad({1.6f, -1.0f, 0.5f}, {0, 2, 0}, {2, 0, 0}, 1);
        light.emission.radiance = Rgb(cutOut ? 10.0f : 4.0f);
        if (cutOut) light.alpha = std::make_shared<const Texture>(Texture::constant(Rgb(0.4f)));
        s.meshes.push_back(light);
        TriangleMesh veil = uvQuad(2.5f);  // over the light, facing up
        veil.material = 0;
        veil.alpha = std::make_shared<const Texture>(
            Texture::checkerboard(Rgb(1.0f), Rgb(0.5f)).mapUv({4.0f, 4.0f}, {0.0f, 0.0f}));
        veil.positions = {{-0.3f, -0.3f, 2.5f}, {0.3f, -0.3f, 2.5f}, {0.3f, 0.3f, 2.5f}, {-0.3f, 0.3f, 2.5f}};
        s.meshes.push_back(veil);
        return s;
    };
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        const Film a = renderScene(scene(true), 2, accelerator),
                   b = renderScene(scene(false), 2, accelerator);
        double sumA = 0.0, sumB = 0.0, sumDiff2 = 0.0;
        const int pixels = a.width() * a.height();
        for (int y = 0; y < a.height(); ++y)
            for (int x = 0; x < a.width(); ++x) {
                const double ma = a.at(x, y).mean().luminance(), mb = b.at(x, y).mean().luminance();
                sumA += ma;
                sumB += mb;
                sumDiff2 += (ma - mb) * (ma - mb);
            }
        const double meanA = sumA / pixels, meanB = sumB / pixels;
        // The pixels' differences scatter around the mean difference; their spread bounds its error.
        const double standardError = std::sqrt(sumDiff2 / pixels / pixels);
        std::printf("%s: cut-out emitter %.5f, dimmer opaque emitter %.5f, standard error %.5f\n",
                    std::string(acceleratorKindName(accelerator)).c_str(), meanA, meanB, standardError);
        EXPECT_GT(meanB, 0.01);
        EXPECT_NEAR(meanA, meanB, 5.0 * standardError);
    }
}

}  // namespace
}  // namespace penumbra
