// The environment light's importance sampling: directions are drawn with a density proportional
// to the map's luminance times sin(theta) (chi-square over the texels), pdf() agrees with the
// density sample() reports and integrates to 1 over the sphere, and the map's orientation is the
// documented one.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/sampling.h"
#include "lights/environment_light.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

// A small map of varied luminance, some texels black, one bright "sun" texel.
EnvironmentImage variedImage(int width, int height) {
    EnvironmentImage image{width, height, {}};
    test::UniformRng rng(11);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float v = rng.next();
            Rgb c = v < 0.15f ? Rgb(0.0f) : Rgb(v, 0.5f * v + 0.1f, 1.0f - v);
            if (x == 3 && y == 2) c = Rgb(50.0f, 45.0f, 40.0f);
            image.texels.push_back(c);
        }
    return image;
}

// The texel a world direction falls in, for a light with the given rotation.
int texelOf(Vec3f direction, const Transform& rotation, int width, int height) {
    const Vec2f st = EnvironmentLight::directionToImage(normalize(rotation.inverse().applyVector(direction)));
    const int x = std::min(int(st.x * float(width)), width - 1), y = std::min(int(st.y * float(height)), height - 1);
    return y * width + x;
}

void expectSamplingMatchesLuminanceTimesSine(const Transform& rotation) {
    const int width = 16, height = 8;
    const EnvironmentImage image = variedImage(width, height);
    const EnvironmentLight light = EnvironmentLight::fromImage(image, Rgb(1.0f), rotation);
    // Expected: each texel's probability is luminance * sin(theta at its row centre) over the sum.
    std::vector<double> weight(size_t(width * height));
    double total = 0.0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double w = double(image.at(x, y).luminance()) * std::sin(kPi * (y + 0.5) / height);
            weight[size_t(y * width + x)] = w;
            total += w;
        }
    const int n = 400000;
    std::vector<double> observed(weight.size(), 0.0), expected(weight.size());
    for (size_t i = 0; i < weight.size(); ++i) expected[i] = n * weight[i] / total;
    test::UniformRng rng(5);
    int pdfMismatches = 0;
    for (int i = 0; i < n; ++i) {
        const auto s = light.sample(rng.next2D());
        ASSERT_TRUE(s.has_value());
        observed[size_t(texelOf(s->direction, rotation, width, height))] += 1.0;
        // The density sample() reports is the one pdf() gives for its direction.
        if (std::abs(light.pdf(s->direction) - s->pdf) > 1e-3f * s->pdf) ++pdfMismatches;
        // And the radiance is that of the direction's texel.
        if (i < 1000) EXPECT_EQ(s->radiance, light.radiance(s->direction));
    }
    // A few samples land within float rounding of a texel edge, where the two may differ.
    EXPECT_LE(pdfMismatches, n / 10000);
    const test::ChiSquareResult chi = test::chiSquareTest(observed, expected);
    EXPECT_GT(chi.pValue, 1e-4) << chi.describe();
}

TEST(EnvironmentSampling, MatchesLuminanceTimesSineChiSquare) { expectSamplingMatchesLuminanceTimesSine(Transform()); }

TEST(EnvironmentSampling, MatchesLuminanceTimesSineRotated) {
    expectSamplingMatchesLuminanceTimesSine(Transform::rotate(70.0f, {0.3f, 1.0f, -0.2f}));
}

// The density integrates to 1 over the sphere: E[pdf(w) / p_uniform(w)] = 1 for uniform w. The
// ratio is at most max(pdf) * 4 pi; its variance is bounded by E[ratio^2], estimated alongside.
TEST(EnvironmentSampling, DensityIntegratesToOne) {
    const EnvironmentLight light = EnvironmentLight::fromImage(variedImage(16, 8), Rgb(1.0f), Transform());
    test::UniformRng rng(3);
    const int n = 1 << 20;
    double sum = 0.0, sumSquares = 0.0;
    for (int i = 0; i < n; ++i) {
        const double ratio = light.pdf(sampleUniformSphere(rng.next2D())) / uniformSpherePdf();
        sum += ratio;
        sumSquares += ratio * ratio;
    }
    const double mean = sum / n, variance = sumSquares / n - mean * mean;
    EXPECT_TRUE(test::withinSigmas(mean, 1.0, std::sqrt(variance / n)));
}

// The documented orientation: +y up is the top row, the image centre looks along +z, a quarter
// of the width along +x.
TEST(EnvironmentSampling, OrientationOfTheMap) {
    const int width = 8, height = 4;
    EnvironmentImage image{width, height, std::vector<Rgb>(size_t(width * height), Rgb(0.0f))};
    image.texels[size_t(0 * width + 0)] = Rgb(1.0f, 0.0f, 0.0f);              // top row: up
    image.texels[size_t(2 * width + width / 2)] = Rgb(0.0f, 1.0f, 0.0f);      // centre, just below the horizon: +z
    image.texels[size_t(1 * width + width / 4)] = Rgb(0.0f, 0.0f, 1.0f);      // a quarter across, above the horizon: +x
    const EnvironmentLight light = EnvironmentLight::fromImage(image, Rgb(1.0f), Transform());
    EXPECT_EQ(light.radiance({0.001f, 1.0f, -0.01f}), Rgb(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(light.radiance({-0.01f, -0.2f, 1.0f}), Rgb(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(light.radiance({1.0f, 0.2f, 0.01f}), Rgb(0.0f, 0.0f, 1.0f));
    // Rotated 90 degrees about +y, what was along +x now arrives from -z.
    const EnvironmentLight turned = EnvironmentLight::fromImage(image, Rgb(2.0f), Transform::rotate(90.0f, {0, 1, 0}));
    EXPECT_EQ(turned.radiance({0.01f, 0.2f, -1.0f}), Rgb(0.0f, 0.0f, 2.0f));
}

// A constant environment is sampled uniformly, as the scene's "background" always was.
TEST(EnvironmentSampling, ConstantIsUniform) {
    const EnvironmentLight light = EnvironmentLight::constant(Rgb(0.5f));
    const auto s = light.sample({0.3f, 0.7f});
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->direction, sampleUniformSphere({0.3f, 0.7f}));
    EXPECT_EQ(s->pdf, uniformSpherePdf());
    EXPECT_EQ(light.pdf(s->direction), uniformSpherePdf());
    EXPECT_EQ(light.average(), Rgb(0.5f));
}

}  // namespace
}  // namespace penumbra
