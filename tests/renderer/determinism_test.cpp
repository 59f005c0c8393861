// The same scene, seed and sample count give the same film bit for bit, whatever the thread
// count, the tile size, or how the sample range is split.
#include <gtest/gtest.h>

#include <cstring>

#include "renderer/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

Film renderWith(const Scene& scene, RenderOptions options) {
    Film film(scene.film.width, scene.film.height);
    render(scene, options, film);
    return film;
}

bool identical(const Film& a, const Film& b) {
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            if (std::memcmp(&a.at(x, y), &b.at(x, y), sizeof(PixelSums)) != 0) return false;
    return true;
}

TEST(Determinism, OneAndTwoThreadsGiveTheSameFilm) {
    for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Independent}) {
        Scene scene = testing::makeSmallBoxScene(48, 40, 8);
        scene.settings.sampler = sampler;
        RenderOptions one;
        one.threads = 1;
        RenderOptions two;
        two.threads = 2;
        two.tileSize = 7;  // and a different tiling
        const Film a = renderWith(scene, one), b = renderWith(scene, two);
        EXPECT_TRUE(identical(a, b)) << samplerKindName(sampler);
        EXPECT_GT(a.at(24, 20).mean().luminance(), 0.0f);
    }
}

TEST(Determinism, SeedChangesTheImage) {
    Scene scene = testing::makeSmallBoxScene(24, 20, 4);
    const Film a = renderWith(scene, {});
    scene.settings.seed = 1;
    const Film b = renderWith(scene, {});
    EXPECT_FALSE(identical(a, b));
}

TEST(Determinism, SampleRangesAddUpToTheWholeRender) {
    Scene scene = testing::makeSmallBoxScene(24, 20, 8);
    const Film whole = renderWith(scene, {});
    Film parts(scene.film.width, scene.film.height);
    RenderOptions first;
    first.endSample = 3;
    render(scene, first, parts);
    RenderOptions rest;
    rest.firstSample = 3;
    rest.endSample = 8;
    render(scene, rest, parts);
    // Sums are added in the same order (sample by sample), so even the doubles agree exactly.
    EXPECT_TRUE(identical(whole, parts));
}

}  // namespace
}  // namespace penumbra
