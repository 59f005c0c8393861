// The environment light's importance sampling: directions are drawn with a density proportional
// to the map's luminance times each texel's solid angle (sin(theta) for the equirectangular map, 1
// for the equal-area one; chi-square over the texels), pdf() agrees with the density sample()
// reports and integrates to 1 over the sphere, the equal-area map covers equal solid angles, and
// each map's orientation is the documented one.
#include "lights/environment_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/sampling.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

// A small map of varied luminance, some texels black, one bright "sun" texel.
EnvironmentImage variedImage(int width, int height,
                             EnvironmentMapping mapping = EnvironmentMapping::Equirectangular) {
    EnvironmentImage image{width, height, {}, mapping};
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
int texelOf(Vec3f direction, const Transform& rotation, int width, int height,
            EnvironmentMapping mapping = EnvironmentMapping::Equirectangular) {
    const Vec2f st =
        EnvironmentLight::directionToImage(normalize(rotation.inverse().applyVector(direction)), mapping);
    const int x = std::min(int(st.x * float(width)), width - 1),
              y = std::min(int(st.y * float(height)), height - 1);
    return y * width + x;
}

void expectSamplingMatchesLuminanceTimesSolidAngle(
    const Transform& rotation, EnvironmentMapping mapping = EnvironmentMapping::Equirectangular) {
    const bool equalArea = mapping == EnvironmentMapping::EqualArea;
    const int width = 16, height = equalArea ? 16 : 8;
    const EnvironmentImage image = variedImage(width, height, mapping);
    const EnvironmentLight light = EnvironmentLight::fromImage(image, Rgb(1.0f), rotation);
    // Expected: each texel's probability is luminance * its solid angle over the sum: sin(theta at
    // its row centre) for the equirectangular map, the same for all texels of the equal-area one.
    std::vector<double> weight(size_t(width * height));
    double total = 0.0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double w =
                double(image.at(x, y).luminance()) * (equalArea ? 1.0 : std::sin(kPi * (y + 0.5) / height));
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
        observed[size_t(texelOf(s->direction, rotation, width, height, mapping))] += 1.0;
        // The density sample() reports is the one pdf() gives for its direction.
        if (std::abs(light.pdf(s->direction) - s->pdf) > 1e-3f * s->pdf) ++pdfMismatches;
        // And the radiance is that of the direction's texel.
        if (i < 1000) {
            EXPECT_EQ(s->radiance, light.radiance(s->direction));
        }
    }
    // A few samples land within float rounding of a texel edge, where the two may differ.
    EXPECT_LE(pdfMismatches, n / 10000);
    const test::ChiSquareResult chi = test::chiSquareTest(observed, expected);
    EXPECT_GT(chi.pValue, 1e-4) << chi.describe();
}

TEST(EnvironmentSampling, MatchesLuminanceTimesSineChiSquare) {
    expectSamplingMatchesLuminanceTimesSolidAngle(Transform());
}

TEST(EnvironmentSampling, MatchesLuminanceTimesSineRotated) {
    expectSamplingMatchesLuminanceTimesSolidAngle(Transform::rotate(70.0f, {0.3f, 1.0f, -0.2f}));
}

TEST(EnvironmentSampling, EqualAreaMatchesLuminanceChiSquare) {
    expectSamplingMatchesLuminanceTimesSolidAngle(Transform(), EnvironmentMapping::EqualArea);
    expectSamplingMatchesLuminanceTimesSolidAngle(Transform::rotate(70.0f, {0.3f, 1.0f, -0.2f}),
                                                  EnvironmentMapping::EqualArea);
}

// The density integrates to 1 over the sphere: E[pdf(w) / p_uniform(w)] = 1 for uniform w. The
// ratio is at most max(pdf) * 4 pi; its variance is bounded by E[ratio^2], estimated alongside.
TEST(EnvironmentSampling, DensityIntegratesToOne) {
    for (const EnvironmentImage& image :
         {variedImage(16, 8), variedImage(16, 16, EnvironmentMapping::EqualArea)}) {
        const EnvironmentLight light = EnvironmentLight::fromImage(image, Rgb(1.0f), Transform());
        test::UniformRng rng(3);
        const int n = 1 << 20;
        double sum = 0.0, sumSquares = 0.0;
        for (int i = 0; i < n; ++i) {
            const double ratio = light.pdf(sampleUniformSphere(rng.next2D())) / uniformSpherePdf();
            sum += ratio;
            sumSquares += ratio * ratio;
        }
        const double mean = sum / n, variance = sumSquares / n - mean * mean;
        EXPECT_TRUE(test::withinSigmas(mean, 1.0, std::sqrt(variance / n))) << int(image.mapping);
    }
}

// The equal-area map is what its name says, checked without the light's own densities: uniformly
// distributed directions fall uniformly into the cells of the square (chi-square over 12 x 12
// cells), and the map and its inverse undo each other.
TEST(EnvironmentSampling, EqualAreaMapCoversEqualSolidAngles) {
    const int cells = 12, n = 288000;
    std::vector<double> observed(size_t(cells * cells), 0.0),
        expected(observed.size(), double(n) / (cells * cells));
    test::UniformRng rng(17);
    int roundTripMisses = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3f direction = sampleUniformSphere(rng.next2D());
        const Vec2f st = EnvironmentLight::directionToImage(direction, EnvironmentMapping::EqualArea);
        ASSERT_TRUE(st.x >= 0.0f && st.x < 1.0f && st.y >= 0.0f && st.y < 1.0f) << st.x << " " << st.y;
        observed[size_t(int(st.y * cells) * cells + int(st.x * cells))] += 1.0;
        const Vec3f back = EnvironmentLight::imageToDirection(st, EnvironmentMapping::EqualArea);
        if (!(length(back - direction) < 1e-5f)) ++roundTripMisses;
    }
    EXPECT_EQ(roundTripMisses, 0);
    const test::ChiSquareResult chi = test::chiSquareTest(observed, expected);
    EXPECT_GT(chi.pValue, 1e-4) << chi.describe();
}

// The documented orientation: +y up is the top row, the image centre looks along +z, a quarter
// of the width along +x.
TEST(EnvironmentSampling, OrientationOfTheMap) {
    const int width = 8, height = 4;
    EnvironmentImage image{width, height, std::vector<Rgb>(size_t(width * height), Rgb(0.0f))};
    image.texels[size_t(0 * width + 0)] = Rgb(1.0f, 0.0f, 0.0f);  // top row: up
    image.texels[size_t(2 * width + width / 2)] =
        Rgb(0.0f, 1.0f, 0.0f);  // centre, just below the horizon: +z
    image.texels[size_t(1 * width + width / 4)] =
        Rgb(0.0f, 0.0f, 1.0f);  // a quarter across, above the horizon: +x
    const EnvironmentLight light = EnvironmentLight::fromImage(image, Rgb(1.0f), Transform());
    EXPECT_EQ(light.radiance({0.001f, 1.0f, -0.01f}), Rgb(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(light.radiance({-0.01f, -0.2f, 1.0f}), Rgb(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(light.radiance({1.0f, 0.2f, 0.01f}), Rgb(0.0f, 0.0f, 1.0f));
    // Rotated 90 degrees about +y, what was along +x now arrives from -z.
    const EnvironmentLight turned =
        EnvironmentLight::fromImage(image, Rgb(2.0f), Transform::rotate(90.0f, {0, 1, 0}));
    EXPECT_EQ(turned.radiance({0.01f, 0.2f, -1.0f}), Rgb(0.0f, 0.0f, 2.0f));
}

// The documented equal-area orientation: the square's centre looks up, its corners down, the
// middle of its left edge along -x and of its top edge along +z.
TEST(EnvironmentSampling, OrientationOfTheEqualAreaMap) {
    const int size = 9;
    EnvironmentImage image{size, size, std::vector<Rgb>(size_t(size * size), Rgb(0.0f)),
                           EnvironmentMapping::EqualArea};
    image.texels[size_t(4 * size + 4)] = Rgb(1.0f, 0.0f, 0.0f);  // centre: up
    image.texels[size_t(4 * size + 0)] = Rgb(0.0f, 1.0f, 0.0f);  // left edge: -x
    image.texels[size_t(0 * size + 4)] = Rgb(0.0f, 0.0f, 1.0f);  // top edge: +z
    for (int corner : {0, size - 1, size * (size - 1), size * size - 1})
        image.texels[size_t(corner)] = Rgb(1.0f, 1.0f, 0.0f);  // down
    const EnvironmentLight light = EnvironmentLight::fromImage(image, Rgb(1.0f), Transform());
    EXPECT_EQ(light.radiance({0.01f, 1.0f, 0.02f}), Rgb(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(light.radiance({-1.0f, 0.01f, 0.02f}), Rgb(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(light.radiance({0.01f, 0.02f, 1.0f}), Rgb(0.0f, 0.0f, 1.0f));
    EXPECT_EQ(light.radiance({0.0f, -1.0f, 0.0f}), Rgb(1.0f, 1.0f, 0.0f));
    EXPECT_EQ(light.radiance({0.02f, -1.0f, -0.01f}), Rgb(1.0f, 1.0f, 0.0f));
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
