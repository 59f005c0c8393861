// The integrator's light strategies (integrator "strategy"): BSDF sampling alone, light sampling
// alone and both under MIS estimate the same image, and MIS has the least variance where each
// alone fails: Veach's scene (scenes/veach-mis.json), small and large lights on smooth and rough
// plates, at 160x90.
//
// Tolerances: the image means of two strategies differ by less than 5 standard errors of the
// difference (each from the film's per-pixel variance of the mean; pixels are independent). The
// variance claim compares summed per-pixel variances, whose ratio here is several times (measured
// below), far beyond their own sampling noise at 64 spp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"

namespace penumbra {
namespace {

struct ImageEstimate {
    double mean[3] = {0, 0, 0};
    double varianceOfMean[3] = {0, 0, 0};  // of the image mean
    // Of the pixel means, relative as `converge` measures error: v / (mean^2 + 0.01), summed over
    // pixels and channels, so that the pixels on a light's edge (0 or 3040, whatever the
    // strategy) do not drown the rest.
    double summedVariance = 0;
};

ImageEstimate renderWith(LightStrategy strategy) {
    Scene scene = loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "scenes" / "veach-mis.json");
    scene.film.width = 160;
    scene.film.height = 90;
    scene.film.samplesPerPixel = 64;
    scene.integrator.strategy = strategy;
    scene.settings.seed = 7;
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    ImageEstimate e;
    const double n = double(film.width()) * film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Rgb m = film.at(x, y).mean(), v = film.at(x, y).varianceOfMean();
            for (int c = 0; c < 3; ++c) {
                e.mean[c] += m[c] / n;
                e.varianceOfMean[c] += v[c] / (n * n);
                e.summedVariance += v[c] / (double(m[c]) * m[c] + 0.01);
            }
        }
    return e;
}

TEST(LightStrategy, AllThreeEstimateTheSameImageAndMisHasTheLeastVariance) {
    const ImageEstimate mis = renderWith(LightStrategy::Mis);
    const ImageEstimate bsdf = renderWith(LightStrategy::Bsdf);
    const ImageEstimate light = renderWith(LightStrategy::Light);
    for (int c = 0; c < 3; ++c) {
        for (const ImageEstimate* other : {&bsdf, &light}) {
            const double sigma = std::sqrt(mis.varianceOfMean[c] + other->varianceOfMean[c]);
            EXPECT_LT(std::abs(mis.mean[c] - other->mean[c]), 5.0 * sigma)
                << "channel " << c << ": " << mis.mean[c] << " vs " << other->mean[c] << " ("
                << (other == &bsdf ? "bsdf" : "light") << ")";
        }
    }
    std::printf("summed pixel variance: mis %.4g, bsdf %.4g (x%.1f), light %.4g (x%.1f)\n",
                mis.summedVariance, bsdf.summedVariance, bsdf.summedVariance / mis.summedVariance,
                light.summedVariance, light.summedVariance / mis.summedVariance);
    EXPECT_LT(2.0 * mis.summedVariance, bsdf.summedVariance);
    EXPECT_LT(2.0 * mis.summedVariance, light.summedVariance);
}

}  // namespace
}  // namespace penumbra
