// Perlin's gradient noise (core/perlin_noise.h): the properties that define it. It is 0 at every
// lattice point (each corner's gradient is dotted with a zero offset there), repeats every 256
// units, stays within about [-1, 1] (checked: |n| <= 1.1), averages 0 (the twelve edge gradients
// sum to 0: over 10^5 uniform points the mean is within 5 standard errors of 0), and its gradient
// (a forward difference of 0.01) is its slope: a central difference of a step 100 times smaller.
#include "core/perlin_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace penumbra {
namespace {

TEST(PerlinNoise, VanishesOnTheLatticeAndRepeatsEvery256Units) {
    for (int x = -3; x <= 3; ++x)
        for (int y = -3; y <= 3; ++y)
            for (int z = -3; z <= 3; ++z) EXPECT_EQ(perlinNoise(Vec3f(float(x), float(y), float(z))), 0.0f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 16.0f);
    int nonZero = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3f p(u(rng), u(rng), u(rng));
        const float n = perlinNoise(p);
        EXPECT_NEAR(perlinNoise(p + Vec3f(256.0f, 0.0f, 0.0f)), n, 1e-4f);
        EXPECT_NEAR(perlinNoise(p + Vec3f(0.0f, 256.0f, -256.0f)), n, 1e-4f);
        nonZero += n != 0.0f;
    }
    EXPECT_GT(nonZero, 990);
}

TEST(PerlinNoise, IsBoundedWithMeanZero) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-300.0f, 300.0f);
    const int n = 100000;
    double sum = 0, sumSquares = 0;
    for (int i = 0; i < n; ++i) {
        const float v = perlinNoise(Vec3f(u(rng), u(rng), u(rng)));
        ASSERT_LE(std::abs(v), 1.1f);
        sum += v;
        sumSquares += double(v) * v;
    }
    const double mean = sum / n, variance = sumSquares / n - mean * mean;
    EXPECT_GT(variance, 0.01);  // not a constant
    EXPECT_LT(std::abs(mean), 5.0 * std::sqrt(variance / n));
}

TEST(PerlinNoise, TheGradientIsTheNoisesSlope) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(0.0f, 8.0f);
    for (int i = 0; i < 200; ++i) {
        const Vec3f p(u(rng), u(rng), u(rng));
        const Vec3f g = perlinNoiseGradient(p);
        constexpr float h = 1e-4f;
        const Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (int a = 0; a < 3; ++a) {
            // The forward difference of 0.01 against the slope at its midpoint, where the
            // quintic blend's curvature bounds their difference by about 0.01 * 10.
            const Vec3f mid = p + axes[a] * 0.005f;
            const float slope = (perlinNoise(mid + axes[a] * h) - perlinNoise(mid - axes[a] * h)) / (2 * h);
            EXPECT_NEAR(g[a], slope, 0.1f) << i << " axis " << a;
        }
    }
}

}  // namespace
}  // namespace penumbra
