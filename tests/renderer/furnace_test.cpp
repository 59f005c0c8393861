// Furnace scenes: a camera inside a closed sphere whose Lambert wall has albedo a and emits Le on
// its inside. Every path sees Le at each vertex and keeps a fraction a of its throughput at each
// bounce, so the radiance everywhere is the geometric series Le (1 + a + a^2 + ...) = Le / (1 - a).
// Russian roulette is on from the first bounce: a biased termination rule would show here.
#include <gtest/gtest.h>

#include <cmath>

#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

struct FurnaceEstimate {
    double mean;
    double standardError;  // of the image mean
};

FurnaceEstimate renderFurnace(float albedo, float emitted, SamplerKind sampler, int rouletteStart) {
    Scene scene;
    scene.film = {32, 32, 64, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0.1f, -0.2f, 0.05f};
    scene.camera.lookAt = {0.5f, 0.3f, -1.0f};
    scene.camera.verticalFovDegrees = 90.0f;
    scene.integrator.maxDepth = 100000;  // truncation bias a^100000: nil
    scene.integrator.rouletteStartDepth = rouletteStart;
    scene.settings.sampler = sampler;
    scene.settings.seed = 7;
    scene.materials = {testing::makeLambert(Rgb(albedo))};
    Sphere sphere;
    sphere.center = {0.0f, 0.0f, 0.0f};
    sphere.radius = 1.0f;
    sphere.emission.radiance = Rgb(emitted);
    sphere.emission.twoSided = true;  // the inside of a sphere is its back side
    scene.spheres.push_back(sphere);

    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);

    // Each channel is the same; use green. The per-sample variance comes from the film's sums of
    // squares; pixels are independent, so the image mean's variance is sigma^2 / (all samples).
    double sum = 0, sumSquares = 0, count = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const PixelSums& p = film.at(x, y);
            sum += p.radiance[1];
            sumSquares += p.radianceSquared[1];
            count += p.weight;
        }
    const double mean = sum / count;
    const double variance = sumSquares / count - mean * mean;
    return {mean, std::sqrt(variance / count)};
}

// 5 standard errors: a false failure has probability below 1e-6 per check. Stratification only
// lowers the true error below the i.i.d. estimate, so the bound is conservative for it.
void expectFurnace(float albedo, float emitted, SamplerKind sampler, int rouletteStart) {
    const FurnaceEstimate e = renderFurnace(albedo, emitted, sampler, rouletteStart);
    const double expected = emitted / (1.0 - albedo);
    EXPECT_GT(e.standardError, 0.0);
    EXPECT_NEAR(e.mean, expected, 5.0 * e.standardError + 1e-4 * expected)
        << "albedo " << albedo << " sampler " << samplerKindName(sampler) << " roulette from "
        << rouletteStart;
}

TEST(Furnace, HalfAlbedoWithRouletteFromFirstBounce) {
    expectFurnace(0.5f, 1.0f, SamplerKind::Independent, 0);
}
TEST(Furnace, HighAlbedoWithRouletteFromFirstBounce) {
    expectFurnace(0.8f, 0.5f, SamplerKind::Independent, 0);
}
TEST(Furnace, HighAlbedoStratifiedRouletteFromThirdBounce) {
    expectFurnace(0.8f, 2.0f, SamplerKind::Stratified, 3);
}
TEST(Furnace, BlackWallShowsOnlyEmission) {
    const FurnaceEstimate e = renderFurnace(0.0f, 1.5f, SamplerKind::Stratified, 0);
    EXPECT_NEAR(e.mean, 1.5, 1e-6);
}

// Truncation: with max depth D and no roulette, the series stops after D bounces:
// Le (1 - a^(D+1)) / (1 - a). This checks the meaning of max_depth.
TEST(Furnace, MaxDepthTruncatesTheSeries) {
    for (int depth : {0, 1, 3}) {
        Scene scene;
        scene.film = {16, 16, 64, FilterKind::Box, 0.5f};
        scene.camera.lookFrom = {0.0f, 0.0f, 0.0f};
        scene.camera.lookAt = {0.0f, 0.0f, -1.0f};
        scene.integrator.maxDepth = depth;
        scene.integrator.rouletteStartDepth = 1000;
        scene.settings.sampler = SamplerKind::Independent;
        scene.materials = {testing::makeLambert(Rgb(0.5f))};
        Sphere sphere;
        sphere.radius = 1.0f;
        sphere.emission = {Rgb(1.0f), true, nullptr};
        scene.spheres.push_back(sphere);
        Film film(16, 16);
        render(scene, RenderOptions{}, film);
        double sum = 0, sumSquares = 0, count = 0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                sum += film.at(x, y).radiance[0];
                sumSquares += film.at(x, y).radianceSquared[0];
                count += film.at(x, y).weight;
            }
        const double mean = sum / count;
        const double standardError = std::sqrt(std::max(0.0, sumSquares / count - mean * mean) / count);
        const double expected = (1.0 - std::pow(0.5, depth + 1)) / 0.5;
        // The floor of 1e-4 relative covers float rounding in the MIS weights (the estimator is almost
        // noiseless here, because NEE and BSDF sampling of a uniform sphere nearly agree).
        EXPECT_NEAR(mean, expected, 5.0 * standardError + 1e-4 * expected) << "max depth " << depth;
    }
}

}  // namespace
}  // namespace penumbra
