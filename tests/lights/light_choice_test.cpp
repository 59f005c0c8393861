// The choice of a light at a vertex (LightSet::choose, lights/light_bounds.h): the importance is
// conservative (never 0 where the light can light the point), the batch computes the same bits as
// one light at a time, the choice's probabilities sum to 1 and choose() draws by them (chi-square),
// and a value that chooses keeps its stratum within the chosen light.
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

// A triangle's bounds as LightSet builds them for a triangle light of its own.
LightBounds triangleBounds(Vec3f p0, Vec3f p1, Vec3f p2, bool twoSided) {
    LightBounds b;
    b.center = (p0 + p1 + p2) / 3.0f;
    b.radius = std::sqrt(
        std::max({lengthSquared(p0 - b.center), lengthSquared(p1 - b.center), lengthSquared(p2 - b.center)}));
    b.axis = normalize(cross(p1 - p0, p2 - p0));
    b.cosThetaO = 1.0f;
    b.twoSided = twoSided;
    b.phi = 1.0f;
    return b;
}

// Wherever a one-sided triangle lights a point (some point of it has the point in front, within
// the point's hemisphere about either side of its normal, as the importance takes |cos|), the
// importance is positive; where no point of it does, it may be 0, and is for points behind it.
TEST(LightBounds, ImportanceIsPositiveWhereTheTriangleCanLight) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int lit = 0, unlit = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3f p0 = randomPoint(rng, 1.0f), p1 = randomPoint(rng, 1.0f), p2 = randomPoint(rng, 1.0f);
        if (length(cross(p1 - p0, p2 - p0)) < 1e-3f) continue;
        const LightBounds b = triangleBounds(p0, p1, p2, false);
        const Vec3f p = randomPoint(rng, 3.0f), n = randomUnit(rng);
        bool canLight = false;
        for (int k = 0; k < 64 && !canLight; ++k) {
            const Vec2f bary = sampleUniformTriangle({u(rng), u(rng)});
            const Vec3f x = p0 * (1.0f - bary.x - bary.y) + p1 * bary.x + p2 * bary.y;
            canLight = dot(b.axis, p - x) > 1e-4f && std::abs(dot(n, normalize(x - p))) > 1e-4f;
        }
        const float importance = b.importance(p, n);
        ASSERT_TRUE(std::isfinite(importance));
        if (canLight) {
            ++lit;
            ASSERT_GT(importance, 0.0f) << "trial " << trial;
        }
        // Behind the triangle's plane by more than its bounding sphere: nothing can arrive.
        if (dot(b.axis, p - b.center) < -1.01f * b.radius) {
            ++unlit;
            EXPECT_EQ(importance, 0.0f) << "trial " << trial;
        }
    }
    EXPECT_GT(lit, 5000);
    EXPECT_GT(unlit, 1000);
}

// A spot light's bounds are positive inside its cone's end and 0 beyond it (by more than rounding).
TEST(LightBounds, SpotImportanceFollowsTheCone) {
    std::mt19937 rng(12);
    const float cosStart = std::cos(0.3f), cosEnd = std::cos(0.5f);
    LightBounds b;
    b.center = {0.2f, 0.1f, -0.3f};
    b.axis = normalize(Vec3f{0.3f, -1.0f, 0.2f});
    b.cosThetaO = cosStart;
    b.cosThetaE = std::cos(0.5f - 0.3f);
    b.phi = 2.0f;
    int inside = 0, outside = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Vec3f p = randomPoint(rng, 3.0f), n = randomUnit(rng);
        const float cosTheta = dot(normalize(p - b.center), b.axis);
        const float importance = b.importance(p, n);
        if (cosTheta > cosEnd + 1e-4f) {
            ++inside;
            EXPECT_GT(importance, 0.0f);
        } else if (cosTheta < cosEnd - 1e-4f) {
            ++outside;
            EXPECT_EQ(importance, 0.0f);
        }
    }
    EXPECT_GT(inside, 500);
    EXPECT_GT(outside, 5000);
}

// The batch's lanes give the bits one call gives, for every kind of bounds, with and without a
// normal, at points inside bounding spheres and at their centres.
TEST(LightBounds, BatchMatchesOneAtATime) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 2000; ++trial) {
        LightBoundsBatch batch;
        std::vector<LightBounds> bounds(LightBoundsBatch::kCapacity);
        const size_t used = 1 + trial % LightBoundsBatch::kCapacity;
        for (size_t i = 0; i < used; ++i) {
            LightBounds& b = bounds[i];
            b.center = randomPoint(rng, 2.0f);
            b.radius = (i % 3 == 0) ? 0.0f : u(rng);
            b.axis = randomUnit(rng);
            b.phi = u(rng) * 10.0f;
            b.cosThetaO = (i % 4 == 0) ? -1.0f : 2.0f * u(rng) - 1.0f;
            b.cosThetaE = (i % 5 == 0) ? 0.0f : u(rng);
            b.twoSided = i % 2 == 0;
            batch.set(i, b);
        }
        const Vec3f p = trial % 7 == 0 ? bounds[0].center : randomPoint(rng, 3.0f);
        const Vec3f n = trial % 3 == 0 ? Vec3f{} : randomUnit(rng);
        float out[LightBoundsBatch::kCapacity];
        batch.importances(p, n, out);
        for (size_t i = 0; i < used; ++i) {
            const float one = bounds[i].importance(p, n);
            ASSERT_EQ(out[i], one) << "trial " << trial << " light " << i;
            ASSERT_TRUE(std::isfinite(one) && one >= 0.0f);
        }
    }
}

// Two quad lights (four triangles), a point light and an environment: the local choice is on.
Scene sceneWithSeveralLights(bool withEnvironment) {
    Scene scene;
    scene.materials = {testing::makeLambert(Rgb(0.5f))};
    TriangleMesh warm = testing::makeQuad({-2, 2, -1}, {1, 0, 0}, {0, 0, 1}, 0);  // faces -y
    warm.emission.radiance = {5, 4, 3};
    TriangleMesh cool = testing::makeQuad({1, 1, 1}, {0, 1, 0}, {0, 0, 1}, 0);  // faces +x... and two-sided
    cool.emission.radiance = {1, 2, 6};
    cool.emission.twoSided = true;
    scene.meshes = {warm, cool};
    scene.lights.push_back(PointLight{{0.5f, 3.0f, 0.0f}, Rgb(2.0f)});
    if (withEnvironment) scene.environment = EnvironmentLight::constant(Rgb(0.3f));
    return scene;
}

// At any point, the choice's probabilities over the lights sum to 1, and choose() picks each light
// as often as choiceProbability says (chi-square, 200,000 stratified values a point), with the
// probability it reports; its remapped value falls uniformly within each light's share.
TEST(LightChoice, ChoosesEachLightWithTheProbabilityItReports) {
    for (const bool withEnvironment : {false, true}) {
        const Scene scene = sceneWithSeveralLights(withEnvironment);
        const LightSet lights(scene, scene.lights, scene.environment);
        ASSERT_TRUE(lights.choosesLocally());
        std::mt19937 rng(14);
        for (int point = 0; point < 6; ++point) {
            const Vec3f p = randomPoint(rng, 1.5f), n = randomUnit(rng);
            double sum = 0.0;
            std::vector<double> expected(lights.size());
            for (uint32_t l = 0; l < lights.size(); ++l)
                sum += expected[l] = lights.choiceProbability(l, p, n);
            EXPECT_NEAR(sum, 1.0, 1e-5) << "point " << point;
            const int n_samples = 200000;
            std::vector<double> observed(lights.size(), 0.0);
            // Per light: how many remapped values fell in each quarter of [0, 1).
            std::vector<std::vector<double>> quarters(lights.size(), std::vector<double>(4, 0.0));
            for (int i = 0; i < n_samples; ++i) {
                Vec2f uPoint{(float(i) + 0.5f) / float(n_samples), 0.5f};
                const LightSet::Choice choice = lights.choose(uPoint, p, n);
                ASSERT_LT(choice.light, lights.size());
                ASSERT_EQ(choice.probability, lights.choiceProbability(choice.light, p, n));
                ASSERT_GE(uPoint.x, 0.0f);
                ASSERT_LT(uPoint.x, 1.0f);
                observed[choice.light] += 1.0;
                quarters[choice.light][std::min(3, int(uPoint.x * 4.0f))] += 1.0;
            }
            for (uint32_t l = 0; l < lights.size(); ++l) {
                // Stratified values (u = (i + 1/2) / n): a light's interval of [0, 1) holds its
                // probability times n values, to 1 at each end. The weights, their sum and the
                // targets u * total are floats of at most 16 terms (relative rounding below 2e-6),
                // which moves each end by under 2e-6 n values; the bound, 4 + 1e-4 n (24 of
                // 200,000), leaves room for both; a probability off by more than 1.2e-4 fails it.
                EXPECT_NEAR(observed[l], expected[l] * n_samples, 4.0 + 1e-4 * n_samples)
                    << "point " << point << " light " << l;
                for (int q = 0; q < 4 && observed[l] > 1000; ++q)
                    EXPECT_NEAR(quarters[l][q], observed[l] / 4.0, 4.0 + 1e-4 * n_samples)
                        << "light " << l << " quarter " << q;
            }
        }
    }
}

// Eight point lights and the environment: the environment's slot lies past the first eight lanes,
// and the probabilities still sum to 1 at every point.
TEST(LightChoice, ProbabilitiesSumToOneWithAnEmitterPastTheFirstLanes) {
    Scene scene;
    for (int i = 0; i < 8; ++i)
        scene.lights.push_back(PointLight{{float(i) - 3.5f, 2.0f, 0.5f * float(i % 3)}, Rgb(1.0f + i)});
    scene.environment = EnvironmentLight::constant(Rgb(0.2f));
    const LightSet lights(scene, scene.lights, scene.environment);
    ASSERT_TRUE(lights.choosesLocally());
    ASSERT_EQ(lights.size(), 9u);
    std::mt19937 rng(16);
    for (int point = 0; point < 100; ++point) {
        const Vec3f p = randomPoint(rng, 4.0f), n = randomUnit(rng);
        double sum = 0.0;
        for (uint32_t l = 0; l < lights.size(); ++l) sum += lights.choiceProbability(l, p, n);
        EXPECT_NEAR(sum, 1.0, 1e-5) << "point " << point;
        EXPECT_GT(lights.choiceProbability(8, p, n), 0.0f);
    }
}

// Random values: the frequencies against the probabilities by chi-square, at points where the
// lights' importances differ widely (near one light, far from the others).
TEST(LightChoice, RandomValuesPassChiSquare) {
    const Scene scene = sceneWithSeveralLights(true);
    const LightSet lights(scene, scene.lights, scene.environment);
    std::mt19937 rng(15);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const std::vector<Vec3f> points = {{-1.5f, 1.9f, -0.5f}, {1.1f, 1.5f, 1.5f}, {0.0f, 0.0f, 0.0f}};
    std::vector<double> pValues;
    for (const Vec3f& p : points) {
        const Vec3f n{0, 1, 0};
        std::vector<double> observed(lights.size(), 0.0), expected(lights.size());
        const int samples = 100000;
        for (uint32_t l = 0; l < lights.size(); ++l)
            expected[l] = lights.choiceProbability(l, p, n) * samples;
        for (int i = 0; i < samples; ++i) {
            Vec2f uPoint{u(rng), u(rng)};
            observed[lights.choose(uPoint, p, n).light] += 1.0;
        }
        pValues.push_back(test::chiSquareTest(observed, expected).pValue);
    }
    // Three tests at a family-wise 1%.
    for (const double pValue : pValues) EXPECT_GT(pValue, test::sidakAlpha(0.01, 3));
}

// One emitter (a quad light's two triangles) keeps the choice by power: weighing the two halves
// of one light costs more than it gains.
TEST(LightChoice, OneEmitterChoosesByPower) {
    Scene scene = sceneWithSeveralLights(false);
    scene.meshes.pop_back();
    scene.lights.clear();
    const LightSet lights(scene, scene.lights, scene.environment);
    EXPECT_FALSE(lights.choosesLocally());
    EXPECT_FLOAT_EQ(lights.choiceProbability(0, {0, 0, 0}, {0, 1, 0}), 0.5f);
}

}  // namespace
}  // namespace penumbra
