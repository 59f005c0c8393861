// The "watertight" render setting: off, Embree traverses without its robust flag (faster, and
// how Embree's own tutorials build). Only rays that graze a shared edge can find another
// primitive, and hits are recomputed from the primitive found (canonicalizeHit), so the image is
// the same bit for bit wherever every hit agrees, and within noise otherwise.
#include <gtest/gtest.h>

#include <cstdio>

#include "renderer/render.h"
#include "tests/support/film_comparison.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

TEST(Watertight, EmbreesFastTraversalRendersTheSameImageWithinNoise) {
    Scene scene = testing::makeSmallBoxScene(32, 32, 32);
    RenderOptions options;
    options.accelerator = AcceleratorKind::Embree;
    Film robust(32, 32), fast(32, 32);
    ASSERT_TRUE(scene.settings.watertight) << "watertight is the default";
    render(scene, options, robust);
    scene.settings.watertight = false;
    render(scene, options, fast);

    const testing::FilmComparison c = testing::compareWithinNoise(robust, fast);
    std::printf("%d of 1024 pixels bit-identical; image means %.6f (robust) and %.6f (fast)\n",
                c.identicalPixels, c.meanA, c.meanB);
    // With a 5-sigma threshold, 3072 channels expect ~0.002 outliers by chance.
    EXPECT_GE(c.identicalPixels, 1000) << "of 1024";
    EXPECT_LE(c.outlierChannels, 3) << "of 3072 pixel channels";
    EXPECT_NEAR(c.meanB, c.meanA, 0.01 * c.meanA);
    EXPECT_GT(c.meanA, 0.0);
}

}  // namespace
}  // namespace penumbra
