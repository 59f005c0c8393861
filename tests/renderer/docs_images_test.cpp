// The README's headline image is a render of the current code: docs/cornell-box.png (1024 x 1024,
// 64 spp, the Standard view: the sRGB encoding of the linear values, clipped at 1) against a small
// render of the same scene (128 x 128, 64 spp, a box filter over each pixel). Each small pixel
// covers a block of 8 x 8 headline pixels, 4096 samples, so the block's mean (decoded to linear) is
// nearly exact next to the small pixel's, whose standard error the film gives: |difference| /
// standard error is then roughly half-normal, median 0.67. A stale headline (another scene, other
// materials, another integrator: the 34.6 dB of a change of light sampling) pushes the median far
// above 1, and shifts the mean.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

TEST(DocsImages, HeadlineIsARenderOfTheCurrentCode) {
    const fs::path source(PENUMBRA_SOURCE_DIR);
    OIIO::ImageBuf headline((source / "docs" / "cornell-box.png").string());
    ASSERT_TRUE(headline.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << headline.geterror();
    const int size = headline.spec().width, block = size / 128;
    ASSERT_EQ(size, 1024);
    ASSERT_EQ(headline.spec().height, 1024);

    Scene scene = loadScene(source / "scenes" / "cornell-box.json");
    scene.film.width = scene.film.height = 128;
    scene.film.filter = FilterKind::Box;
    scene.film.filterRadius = 0.5f;
    Film film(128, 128);
    render(scene, RenderOptions{}, film);

    std::vector<double> ratios;
    double headlineSum = 0, renderSum = 0;
    std::vector<float> texel(3);
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            double blockMean[3] = {0, 0, 0};
            bool clipped = false;
            for (int j = 0; j < block; ++j)
                for (int i = 0; i < block; ++i) {
                    headline.getpixel(x * block + i, y * block + j, texel.data(), 3);
                    for (int c = 0; c < 3; ++c) {
                        clipped |= texel[c] >= 1.0f;
                        blockMean[c] += srgbToLinear(texel[c]) / (block * block);
                    }
                }
            const Rgb mean = film.at(x, y).mean(), variance = film.at(x, y).varianceOfMean();
            const float rendered[3] = {mean.r, mean.g, mean.b},
                        errors[3] = {variance.r, variance.g, variance.b};
            for (int c = 0; c < 3; ++c) {
                // Clipped blocks (the light, and its brightest reflections) hold no value to compare.
                if (clipped || rendered[c] >= 1.0f) continue;
                headlineSum += blockMean[c];
                renderSum += rendered[c];
                if (errors[c] > 0.0f)
                    ratios.push_back(std::abs(blockMean[c] - rendered[c]) / std::sqrt(errors[c]));
            }
        }
    ASSERT_GT(ratios.size(), 128u * 128u * 2u);
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    const double median = ratios[ratios.size() / 2];
    EXPECT_LT(median, 0.8) << "median |headline - render| / standard error";
    EXPECT_NEAR(renderSum / headlineSum, 1.0, 0.01);
}

}  // namespace
}  // namespace penumbra
