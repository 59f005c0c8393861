// The default scene (scenes/cornell-box.json) against the converged Tungsten reference of the
// same scene (../shared/data/cornell-box-bitterli/reference-tungsten.exr, 1024x1024), both at
// 128x128: the reference is averaged over 8x8 blocks, and we render with a box filter of one
// pixel, so both are area averages over the same pixel.
//
// Checks: (1) mean of each channel within 1.5%; (2) no structured difference: the image is cut in
// 8x8 blocks and every block mean must agree within 5 standard deviations, where the standard
// deviation is derived from our own noise (two renders with different seeds) plus the
// reference's noise (the README's RMSE of 0.011 per reference pixel between two independent
// renders, i.e. 0.011 / sqrt(2) each, averaged over the block's 128 x 128 reference pixels).
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"
#include "tests/support/shared_data.h"

namespace penumbra {
namespace {

constexpr int kSize = 128;
constexpr int kBlocks = 8;  // per axis
constexpr int kBlockPixels = kSize / kBlocks;

struct BlockStats {
    double mean[kBlocks][kBlocks][3] = {};
    double variance[kBlocks][kBlocks][3] = {};  // of the block mean
};

BlockStats blockStatsOf(const Film& film) {
    BlockStats s;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const Rgb m = film.at(x, y).mean(), v = film.at(x, y).varianceOfMean();
            for (int c = 0; c < 3; ++c) {
                s.mean[y / kBlockPixels][x / kBlockPixels][c] += m[c] / (kBlockPixels * kBlockPixels);
                s.variance[y / kBlockPixels][x / kBlockPixels][c] += v[c] / std::pow(kBlockPixels, 4);
            }
        }
    return s;
}

TEST(CornellReference, MatchesTungstenReference) {
    const std::filesystem::path data = PENUMBRA_DATA_DIR;
    const std::filesystem::path referencePath = data / "cornell-box-bitterli" / "reference-tungsten.exr";
    PENUMBRA_SKIP_WITHOUT_SHARED_DATA(referencePath);

    OIIO::ImageBuf reference(referencePath.string());
    ASSERT_TRUE(reference.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << reference.geterror();
    const int refWidth = reference.spec().width, refHeight = reference.spec().height;
    ASSERT_EQ(refWidth % kSize, 0);
    const int factor = refWidth / kSize;
    ASSERT_EQ(refHeight, kSize * factor);

    // Reference averaged down to 128 x 128, then to blocks.
    std::vector<double> ref(kSize * kSize * 3, 0.0);
    std::vector<float> pixel(reference.nchannels());
    for (int y = 0; y < refHeight; ++y)
        for (int x = 0; x < refWidth; ++x) {
            reference.getpixel(x, y, pixel.data());
            for (int c = 0; c < 3; ++c)
                ref[((y / factor) * kSize + x / factor) * 3 + c] += pixel[c] / double(factor * factor);
        }

    Scene scene = loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "scenes" / "cornell-box.json");
    scene.film.width = scene.film.height = kSize;
    scene.film.samplesPerPixel = 128;
    scene.film.filter = FilterKind::Box;
    scene.film.filterRadius = 0.5f;
    Film first(kSize, kSize), second(kSize, kSize);
    scene.settings.seed = 1;
    render(scene, RenderOptions{}, first);
    scene.settings.seed = 2;
    render(scene, RenderOptions{}, second);
    const BlockStats a = blockStatsOf(first), b = blockStatsOf(second);

    // (1) Channel means.
    for (int c = 0; c < 3; ++c) {
        double ours = 0, theirs = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                ours += 0.5 * (first.at(x, y).mean()[c] + second.at(x, y).mean()[c]);
                theirs += ref[(y * kSize + x) * 3 + c];
            }
        EXPECT_NEAR(ours / theirs, 1.0, 0.015) << "channel " << c;
        std::printf("channel %d: mean ours / reference = %.4f\n", c, ours / theirs);
    }

    // (2) Block means. First make sure the noise estimate is honest: the two seeds must agree with
    // each other within it (the sums-of-squares variance over-estimates stratified noise, never
    // under-estimates it).
    const double referenceBlockSigma = 0.011 / std::sqrt(2.0) / (kBlockPixels * factor);
    double worstSeedZ = 0, worstReferenceZ = 0;
    for (int by = 0; by < kBlocks; ++by)
        for (int bx = 0; bx < kBlocks; ++bx)
            for (int c = 0; c < 3; ++c) {
                const double va = a.variance[by][bx][c], vb = b.variance[by][bx][c];
                const double seedZ = std::abs(a.mean[by][bx][c] - b.mean[by][bx][c]) / std::sqrt(va + vb);
                double refBlock = 0;
                for (int y = by * kBlockPixels; y < (by + 1) * kBlockPixels; ++y)
                    for (int x = bx * kBlockPixels; x < (bx + 1) * kBlockPixels; ++x)
                        refBlock += ref[(y * kSize + x) * 3 + c] / (kBlockPixels * kBlockPixels);
                const double ours = 0.5 * (a.mean[by][bx][c] + b.mean[by][bx][c]);
                const double sigma = std::sqrt((va + vb) / 4.0 + referenceBlockSigma * referenceBlockSigma);
                const double referenceZ = std::abs(ours - refBlock) / sigma;
                worstSeedZ = std::max(worstSeedZ, seedZ);
                worstReferenceZ = std::max(worstReferenceZ, referenceZ);
                EXPECT_LT(referenceZ, 5.0) << "block (" << bx << ", " << by << ") channel " << c << ": ours "
                                           << ours << ", reference " << refBlock << ", sigma " << sigma;
            }
    EXPECT_LT(worstSeedZ, 5.0) << "the two seeds disagree beyond their own noise estimate";
    std::printf("worst block z-score: seeds %.2f, against reference %.2f\n", worstSeedZ, worstReferenceZ);
}

}  // namespace
}  // namespace penumbra
