// The example scenes of scenes/: each loads, renders, and gives the same image bit for bit with
// one and with two threads and (but for the rare ray on an edge or a tie) with either backend;
// and on the soft-shadow scene stratified sampling pays off.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"
#include "tests/support/film_comparison.h"
#include "tests/support/render_scene.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::renderScene;

const fs::path kScenes = fs::path(PENUMBRA_SOURCE_DIR) / "scenes";

TEST(ExampleScenes, EveryExampleIsBitIdenticalWithOneAndTwoThreads) {
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(kScenes)) {
        if (entry.path().extension() != ".json") continue;
        Scene scene = loadScene(entry.path());
        scene.film.width = 40;
        scene.film.height = 30;
        scene.film.samplesPerPixel = 4;
        const Film one = renderScene(scene, 1), two = renderScene(scene, 2);
        bool identical = true;
        double total = 0;
        for (int y = 0; y < 30; ++y)
            for (int x = 0; x < 40; ++x) {
                identical &= one.at(x, y) == two.at(x, y);
                total += one.at(x, y).mean().luminance();
            }
        EXPECT_TRUE(identical) << entry.path();
        EXPECT_GT(total, 0.0) << entry.path() << " rendered black";
        ++checked;
    }
    EXPECT_GE(checked, 5);
}

// Each hit is recomputed from the primitive the backend found (canonicalizeHit), so a pixel
// differs only where some path met a different primitive: a ray along an edge or a tie between
// coplanar triangles. Measured at full resolution and 2 spp, that happened in 3 of 1,048,576
// pixels of cornell-box.json (about 1.4e-6 per sample) and in none of the other scenes; 4800
// pixels x 4 samples then expect about 0.03 differing pixels per scene, and 5 is a bound that only
// a systematic difference between the backends would reach. A differing pixel must still agree
// within its noise.
TEST(ExampleScenes, BothBackendsRenderTheSameImages) {
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(kScenes)) {
        if (entry.path().extension() != ".json") continue;
        Scene scene = loadScene(entry.path());
        scene.film.width = 80;
        scene.film.height = 60;
        scene.film.samplesPerPixel = 4;
        const Film embree = renderScene(scene, 2), bvh = renderScene(scene, 2, AcceleratorKind::Bvh);
        const testing::FilmComparison c = testing::compareWithinNoise(embree, bvh);
        EXPECT_GE(c.identicalPixels, 4800 - 5) << entry.path() << ": of 4800 pixels";
        EXPECT_EQ(c.outlierChannels, 0) << entry.path();
        ++checked;
    }
    EXPECT_GE(checked, 5);
}

// RMSE of a render against a reference film, over all pixels and channels.
double rmse(const Film& image, const Film& reference) {
    double sum = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const double d = image.at(x, y).mean()[c] - reference.at(x, y).mean()[c];
                sum += d * d;
            }
    return std::sqrt(sum / (3.0 * image.width() * image.height()));
}

TEST(ExampleScenes, StratifiedSamplingBeatsIndependentOnSoftShadows) {
    Scene scene = loadScene(kScenes / "soft-shadows.json");
    scene.film.width = 72;
    scene.film.height = 48;
    // Reference: 2048 samples per pixel with another seed; its own error (~1/6 of a 64-spp
    // independent render's) inflates both RMSEs alike, which only makes the ratio harder to meet.
    scene.film.samplesPerPixel = 2048;
    scene.settings.seed = 99;
    scene.settings.sampler = SamplerKind::Stratified;
    const Film reference = renderScene(scene, 0);

    scene.film.samplesPerPixel = 64;
    double stratifiedError = 0, independentError = 0;
    // Average over seeds so one lucky render cannot decide (same number of samples: same time).
    for (uint64_t seed : {1, 2, 3}) {
        scene.settings.seed = seed;
        scene.settings.sampler = SamplerKind::Stratified;
        stratifiedError += rmse(renderScene(scene, 0), reference);
        scene.settings.sampler = SamplerKind::Independent;
        independentError += rmse(renderScene(scene, 0), reference);
    }
    std::printf("RMSE at 64 spp: stratified %.5f, independent %.5f, ratio %.3f\n", stratifiedError / 3,
                independentError / 3, stratifiedError / independentError);
    EXPECT_LE(stratifiedError, 0.8 * independentError);
}

}  // namespace
}  // namespace penumbra
