// Aperture shapes: pbrt-v4's built-in images (normalized so as much light passes as through the
// round aperture), sampling in proportion to an image (chi-square), and the out-of-focus image of
// a point light, which is the aperture's image (correlation), through a thin lens.
#include "cameras/aperture.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/hash.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/aperture_correlation.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

double meanOf(const ApertureImage& image) {
    double sum = 0;
    for (float v : image.values) sum += v;
    return sum / double(image.values.size());
}

TEST(Aperture, BuiltinImagesPassTheLightOfTheRoundAperture) {
    for (const char* name : {"gaussian", "square", "pentagon", "star"}) {
        const auto image = builtinApertureImage(name);
        ASSERT_TRUE(image) << name;
        EXPECT_EQ(image->width, 256);
        EXPECT_NEAR(meanOf(*image), kPi / 4.0, 1e-5) << name;
    }
    EXPECT_FALSE(builtinApertureImage("hexagon"));
    // The square covers the middle half of each axis and nothing else.
    const ApertureImage square = *builtinApertureImage("square");
    const Aperture aperture = Aperture::image(square);
    EXPECT_GT(aperture.transmission({0.45f, -0.45f}), 0.0f);
    EXPECT_EQ(aperture.transmission({0.55f, 0.0f}), 0.0f);
    EXPECT_EQ(aperture.transmission({0.0f, -0.6f}), 0.0f);
    EXPECT_EQ(aperture.transmission({1.5f, 0.0f}), 0.0f);
}

TEST(Aperture, BlackImagesAreRefused) {
    ApertureImage black{4, 4, std::vector<float>(16, 0.0f)};
    EXPECT_THROW(normalizeApertureImage(black), InputError);
    EXPECT_THROW(Aperture::image(black), InputError);
}

TEST(Aperture, RoundAndPolygonTransmission) {
    const Aperture round;
    EXPECT_EQ(round.transmission({0.7f, 0.7f}), 1.0f);
    EXPECT_EQ(round.transmission({0.72f, 0.72f}), 0.0f);
    const Aperture square = Aperture::polygon(4, 45.0f);  // vertices at 45, 135, ... degrees
    EXPECT_EQ(square.transmission({0.69f, -0.69f}), 1.0f);
    EXPECT_EQ(square.transmission({0.70f, 0.0f}), 1.0f);  // the edges are at +-sqrt(1/2)
    EXPECT_EQ(square.transmission({0.72f, 0.0f}), 0.0f);
    EXPECT_EQ(square.transmission({0.0f, -0.72f}), 0.0f);
}

// Samples of the star image binned 16 x 16 against each bin's share of the image's values. The
// statistic is chi-square with (bins that can be hit - 1) degrees of freedom k: mean k, standard
// deviation sqrt(2k); 6 standard deviations above the mean fails.
TEST(Aperture, ImageSamplesFollowTheTransmission) {
    const ApertureImage star = *builtinApertureImage("star");
    const Aperture aperture = Aperture::image(star);
    constexpr int kBins = 16, kSamples = 400000;
    const int texelsPerBin = star.width / kBins;
    std::vector<double> expected(kBins * kBins, 0.0), observed(kBins * kBins, 0.0);
    double total = 0;
    for (int y = 0; y < star.height; ++y)
        for (int x = 0; x < star.width; ++x) {
            const float v = star.values[size_t(y) * star.width + x];
            expected[size_t(y / texelsPerBin) * kBins + size_t(x / texelsPerBin)] += v;
            total += v;
        }
    for (int i = 0; i < kSamples; ++i) {
        const uint64_t h = hashWords(99, uint64_t(i));
        const Vec2f p = aperture.sample({bitsToUnitFloat(uint32_t(h)), bitsToUnitFloat(uint32_t(h >> 32))});
        ASSERT_GT(aperture.transmission(p), 0.0f) << "a sample where no light passes";
        const int column = std::clamp(int((p.x + 1.0f) * 0.5f * kBins), 0, kBins - 1);
        const int row = std::clamp(int((1.0f - p.y) * 0.5f * kBins), 0, kBins - 1);
        observed[size_t(row) * kBins + size_t(column)] += 1.0;
    }
    double chi2 = 0;
    int bins = 0;
    for (size_t i = 0; i < expected.size(); ++i) {
        const double e = expected[i] / total * kSamples;
        if (e == 0.0) {
            EXPECT_EQ(observed[i], 0.0) << "bin " << i;
            continue;
        }
        chi2 += (observed[i] - e) * (observed[i] - e) / e;
        ++bins;
    }
    const double k = bins - 1;
    EXPECT_LT(chi2, k + 6.0 * std::sqrt(2.0 * k)) << bins << " bins";
}

// A point light far behind the focus plane through a thin lens with the star aperture: its blur
// is the star, upright, of the thin-lens radius R = A |1/F - 1/d| in image-plane units. The film
// around the blur's centre, sampled on the aperture image's grid, correlates with the image; the
// image mirrored left to right (the star is not symmetric that way) correlates less.
TEST(Aperture, OutOfFocusPointImagesToTheApertureImage) {
    constexpr int kSize = 128;
    constexpr float kFov = 30.0f;
    const float pixelsPerUnit = 0.5f * kSize / std::tan(0.5f * kFov * kPi / 180.0f);
    const float aperture = 0.4f, focus = 2.0f, depth = 8.0f;
    Scene scene;
    scene.film = {kSize, kSize, 1024, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0, 0, 0};
    scene.camera.lookAt = {0, 0, -1};
    scene.camera.verticalFovDegrees = kFov;
    scene.camera.apertureRadius = aperture;
    scene.camera.focusDistance = focus;
    scene.camera.apertureImage = *builtinApertureImage("star");
    scene.integrator.maxDepth = 0;
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    Sphere sphere;
    sphere.center = {0.0f, 0.0f, -depth};
    // Large enough to be hit often (its own image, 4.5 pixels in radius, blurs the star's points
    // a little), small against the 36-pixel blur.
    sphere.radius = 0.15f;
    sphere.emission.radiance = Rgb(1.0f);
    scene.spheres.push_back(sphere);
    Film film(kSize, kSize);
    render(scene, RenderOptions{}, film);

    const float blurRadius = aperture * std::abs(1.0f / focus - 1.0f / depth) * pixelsPerUnit;
    ASSERT_GT(blurRadius, 20.0f);
    const Aperture star = Aperture::image(scene.camera.apertureImage);
    // The blur is centred on the image's centre (the chief ray); a pixel's noise is about 20%.
    const double upright =
        testing::apertureCorrelation(film, star, 0.5 * kSize, 0.5 * kSize, blurRadius, false);
    const double mirrored =
        testing::apertureCorrelation(film, star, 0.5 * kSize, 0.5 * kSize, blurRadius, true);
    EXPECT_GT(upright, 0.9);
    EXPECT_LT(mirrored, upright - 0.1);
}

}  // namespace
}  // namespace penumbra
