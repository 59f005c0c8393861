// The light tree (lights/light_tree.h) and LightSet's choice through it among many lights: node
// bounds are conservative (a union's importance is positive wherever either part's is), a light's
// probabilities at a point sum to 1 and choose() draws by them (chi-square), with the probability
// it reports; a light beside the point is chosen far more often than its power share; the depth
// stays bounded whatever the lights' layout.
#include "lights/light_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/sampling.h"
#include "lights/light_bounds.h"
#include "lights/light_set.h"
#include "tests/support/random_vectors.h"
#include "tests/support/scene_builders.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using testing::randomPoint;
using testing::randomUnit;

// Bounds of a random light: a small one-sided triangle (one normal), a point light (every
// direction) or a spot light (a cone of emission about its axis), of random power.
LightBounds randomLight(std::mt19937& rng, float extent) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    LightBounds b;
    b.center = randomPoint(rng, extent);
    b.phi = 0.1f + 5.0f * u(rng);
    switch (int(u(rng) * 3.0f)) {
        case 0:
            b.radius = 0.05f + 0.2f * u(rng);
            b.axis = randomUnit(rng);
            b.cosThetaO = 1.0f;
            b.twoSided = u(rng) < 0.3f;
            break;
        case 1:
            break;  // a point light: radius 0, every direction
        default:
            b.axis = randomUnit(rng);
            b.cosThetaO = 0.9f;
            b.cosThetaE = std::cos(0.2f);
            break;
    }
    return b;
}

std::vector<LightBounds> randomLights(std::mt19937& rng, int count, float extent) {
    std::vector<LightBounds> lights;
    for (int i = 0; i < count; ++i) lights.push_back(randomLight(rng, extent));
    return lights;
}

// Wherever a light can contribute (its importance is positive), so can any union that holds it:
// the descent never gives a node 0 where a light below it could light the point. Checked for
// pairs of random lights and for nested unions of several.
TEST(LightTreeBounds, UnionIsPositiveWhereEitherPartIs) {
    std::mt19937 rng(21);
    int positive = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        LightBounds a = randomLight(rng, 2.0f), b = randomLight(rng, 2.0f);
        const LightBounds both = unionOf(a, b);
        const LightBounds c = randomLight(rng, 2.0f);
        const LightBounds three = unionOf(both, c);
        EXPECT_FLOAT_EQ(three.phi, a.phi + b.phi + c.phi);
        for (int k = 0; k < 4; ++k) {
            const Vec3f p = randomPoint(rng, 4.0f), n = randomUnit(rng);
            for (const LightBounds* part : {&a, &b}) {
                if (part->importance(p, n) > 0.0f) {
                    ++positive;
                    ASSERT_GT(both.importance(p, n), 0.0f) << "trial " << trial;
                    ASSERT_GT(three.importance(p, n), 0.0f) << "trial " << trial;
                }
            }
            if (c.importance(p, n) > 0.0f) {
                ASSERT_GT(three.importance(p, n), 0.0f) << "trial " << trial;
            }
        }
    }
    EXPECT_GT(positive, 20000);  // the check ran where it matters
    // The union's sphere holds both spheres and its cone both cones.
    for (int trial = 0; trial < 2000; ++trial) {
        const LightBounds a = randomLight(rng, 2.0f), b = randomLight(rng, 2.0f), u = unionOf(a, b);
        for (const LightBounds* part : {&a, &b}) {
            EXPECT_LE(length(part->center - u.center) + part->radius, u.radius * (1.0f + 1e-5f));
            const float angle = std::atan2(length(cross(part->axis, u.axis)), dot(part->axis, u.axis));
            const float partSpread = std::acos(std::clamp(part->cosThetaO, -1.0f, 1.0f));
            if (u.cosThetaO > -1.0f) {
                EXPECT_LE(angle + partSpread, std::acos(u.cosThetaO) + 1e-4f) << "trial " << trial;
            }
        }
    }
}

// At random points, the probabilities of all lights sum to 1; stratified values choose each light
// as often as probability() says (each light's interval of [0, 1) holds its probability times n
// values, to rounding: the bound allows 1e-4 n), with exactly the probability it reports, and
// the value left for the light's point falls uniformly within its share.
TEST(LightTree, ChoosesEachLightWithTheProbabilityItReports) {
    std::mt19937 rng(22);
    const std::vector<LightBounds> bounds = randomLights(rng, 300, 5.0f);
    const LightTree tree(bounds);
    ASSERT_FALSE(tree.empty());
    EXPECT_LT(tree.nodeCount(), bounds.size() / 2);  // up to 8 children a node
    for (int point = 0; point < 6; ++point) {
        const Vec3f p = randomPoint(rng, 5.0f), n = randomUnit(rng);
        double sum = 0.0;
        std::vector<double> expected(bounds.size());
        for (uint32_t l = 0; l < bounds.size(); ++l) sum += expected[l] = tree.probability(l, p, n);
        EXPECT_NEAR(sum, 1.0, 1e-5) << "point " << point;
        const int samples = 300000;
        std::vector<double> observed(bounds.size(), 0.0), lowerHalf(bounds.size(), 0.0);
        for (int i = 0; i < samples; ++i) {
            float u = (float(i) + 0.5f) / float(samples);
            const LightTree::Choice choice = tree.choose(u, p, n);
            ASSERT_LT(choice.light, bounds.size());
            ASSERT_EQ(choice.probability, tree.probability(choice.light, p, n));
            ASSERT_GE(u, 0.0f);
            ASSERT_LT(u, 1.0f);
            observed[choice.light] += 1.0;
            lowerHalf[choice.light] += u < 0.5f ? 1.0 : 0.0;
        }
        for (uint32_t l = 0; l < bounds.size(); ++l) {
            EXPECT_NEAR(observed[l], expected[l] * samples, 4.0 + 1e-4 * samples) << "point " << point;
            if (observed[l] > 2000) {
                EXPECT_NEAR(lowerHalf[l], observed[l] / 2.0, 4.0 + 1e-4 * samples);
            }
        }
    }
}

// Random values, at points beside one light and far from all: chi-square of the choices against
// probability() (bins of expected count under 5 pooled).
TEST(LightTree, RandomValuesPassChiSquare) {
    std::mt19937 rng(23);
    const std::vector<LightBounds> bounds = randomLights(rng, 200, 3.0f);
    const LightTree tree(bounds);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const std::vector<Vec3f> points = {bounds[7].center + Vec3f{0.0f, 0.1f, 0.0f}, {0, 0, 0}, {10, 10, 10}};
    std::vector<double> pValues;
    for (const Vec3f& p : points) {
        const Vec3f n{0, 1, 0};
        const int samples = 200000;
        std::vector<double> observed(bounds.size(), 0.0), expected(bounds.size());
        for (uint32_t l = 0; l < bounds.size(); ++l) expected[l] = tree.probability(l, p, n) * samples;
        for (int i = 0; i < samples; ++i) {
            float u = u01(rng);
            observed[tree.choose(u, p, n).light] += 1.0;
        }
        pValues.push_back(test::chiSquareTest(observed, expected).pValue);
    }
    for (const double pValue : pValues) EXPECT_GT(pValue, test::sidakAlpha(0.01, 3));
}

// What the tree is for: 1000 equal point lights on a 10 x 10 x 10 grid; just beside one of them
// its probability is over 10 times its power share of 0.001 (0.018 when written: the nodes that
// hold the point see their lights no nearer than half their radius, so the nearest light stands
// out only in the last levels), and a light at the far corner's is below that share.
TEST(LightTree, ALightBesideThePointIsChosenFarMoreOftenThanByPower) {
    std::vector<LightBounds> bounds;
    for (int x = 0; x < 10; ++x)
        for (int y = 0; y < 10; ++y)
            for (int z = 0; z < 10; ++z) {
                LightBounds b;
                b.center = {float(x), float(y), float(z)};
                b.phi = 1.0f;
                bounds.push_back(b);
            }
    const LightTree tree(bounds);
    const Vec3f p{2.0f, 3.05f, 4.0f};  // 0.05 from light (2, 3, 4)
    const uint32_t beside = 2 * 100 + 3 * 10 + 4, far = 9 * 100 + 9 * 10 + 9;
    EXPECT_GT(tree.probability(beside, p, Vec3f{}), 0.01f);
    EXPECT_LT(tree.probability(far, p, Vec3f{}), 0.001f);
    EXPECT_GT(tree.probability(far, p, Vec3f{}), 0.0f);
    EXPECT_LE(tree.depth(), 6);
}

// No layout makes the tree deeper than kMaxDepth: 100,000 lights at doubling distances along a
// line (each split by cost peels one off), and 5000 lights at one point (no split separates them:
// halved by count). Both still sum to 1. Lights of power 0 or with non-finite bounds are left out.
TEST(LightTree, DepthIsBoundedAndDegenerateLightsAreLeftOut) {
    std::vector<LightBounds> line;
    for (int i = 0; i < 100000; ++i) {
        LightBounds b;
        b.center = {std::ldexp(1.0f, (i % 200) - 100) * (1.0f + float(i) * 1e-5f), 0.0f, 0.0f};
        b.phi = 1.0f;
        line.push_back(b);
    }
    std::vector<LightBounds> stack(5000);
    for (LightBounds& b : stack) b.phi = 2.0f;
    stack[10].phi = 0.0f;
    stack[11].center.x = std::nanf("");
    stack[12].phi = std::numeric_limits<float>::infinity();
    for (const auto* lights : {&line, &stack}) {
        const LightTree tree(*lights);
        EXPECT_LE(tree.depth(), LightTree::kMaxDepth);
        const Vec3f p{0.5f, 1.0f, 0.0f}, n{0, 1, 0};
        double sum = 0.0;
        for (uint32_t l = 0; l < lights->size(); ++l) sum += tree.probability(l, p, n);
        EXPECT_NEAR(sum, 1.0, 1e-4);
    }
    const LightTree tree(stack);
    EXPECT_EQ(tree.probability(10, {0, 1, 0}, {}), 0.0f);
    EXPECT_EQ(tree.probability(11, {0, 1, 0}, {}), 0.0f);
    EXPECT_EQ(tree.probability(12, {0, 1, 0}, {}), 0.0f);
    EXPECT_LE(tree.depth(), 13);  // ceil(log2(4997)) = 13 binary levels from halving, 3 or more to a node
}

// A scene with 40 emitting quads (80 triangle lights, more emitters than LightSet weighs one by
// one), point lights and an environment: LightSet chooses through the tree, the environment by its
// power share; the probabilities sum to 1 and choose() draws by them (chi-square). With
// LightSampler::Power the same scene chooses by power everywhere.
TEST(LightSetTree, ManyEmittersChooseThroughTheTree) {
    Scene scene;
    std::mt19937 rng(24);
    for (int i = 0; i < 40; ++i) {
        const Vec3f corner = randomPoint(rng, 3.0f);
        TriangleMesh quad = testing::makeQuad(corner, {0.3f, 0, 0}, {0, 0, 0.3f}, 0);
        quad.emission.radiance = Rgb(1.0f + float(i % 5));
        scene.meshes.push_back(quad);
    }
    for (int i = 0; i < 5; ++i) scene.lights.push_back(PointLight{randomPoint(rng, 3.0f), Rgb(2.0f)});
    scene.environment = EnvironmentLight::constant(Rgb(0.05f));
    const LightSet lights(scene, scene.lights, scene.environment);
    ASSERT_TRUE(lights.choosesLocally());
    ASSERT_EQ(lights.size(), 86u);
    const uint32_t environment = 85;
    const LightSet byPower(scene, scene.lights, scene.environment, LightSampler::Power);
    EXPECT_FALSE(byPower.choosesLocally());
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    std::vector<double> pValues;
    for (int point = 0; point < 4; ++point) {
        const Vec3f p = randomPoint(rng, 3.0f), n = randomUnit(rng);
        double sum = 0.0;
        std::vector<double> expected(lights.size());
        for (uint32_t l = 0; l < lights.size(); ++l) sum += expected[l] = lights.choiceProbability(l, p, n);
        EXPECT_NEAR(sum, 1.0, 1e-5);
        EXPECT_NEAR(expected[environment], byPower.choiceProbability(environment, p, n), 1e-6);
        const int samples = 200000;
        std::vector<double> observed(lights.size(), 0.0);
        for (int i = 0; i < samples; ++i) {
            Vec2f u{u01(rng), u01(rng)};
            const LightSet::Choice choice = lights.choose(u, p, n);
            ASSERT_EQ(choice.probability, lights.choiceProbability(choice.light, p, n));
            observed[choice.light] += 1.0;
        }
        for (double& e : expected) e *= samples;
        pValues.push_back(test::chiSquareTest(observed, expected).pValue);
    }
    for (const double pValue : pValues) EXPECT_GT(pValue, test::sidakAlpha(0.01, 4));
}

}  // namespace
}  // namespace penumbra
