// The same scene, seed and sample count give the same film bit for bit, whatever the thread
// count, the tile size, or how the sample range is split.
#include <gtest/gtest.h>

#include <utility>

#include "film/film.h"
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
            if (!(a.at(x, y) == b.at(x, y))) return false;
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

// Ranges that cut across Embree's packets of camera rays (8 samples) too, with canonical hits on
// and off (off, the film holds Embree's own hit values, which must not depend on the range).
TEST(Determinism, SampleRangesAddUpToTheWholeRender) {
    for (bool canonicalHits : {true, false}) {
        Scene scene = testing::makeSmallBoxScene(24, 20, 20);
        scene.settings.canonicalHits = canonicalHits;
        const Film whole = renderWith(scene, {});
        Film parts(scene.film.width, scene.film.height);
        for (auto [first, end] : {std::pair{0u, 3u}, {3u, 13u}, {13u, 20u}}) {
            RenderOptions part;
            part.firstSample = first;
            part.endSample = end;
            render(scene, part, parts);
        }
        EXPECT_TRUE(identical(whole, parts)) << "canonical hits " << canonicalHits;
    }
}

}  // namespace
}  // namespace penumbra
