// The environment light in renders: the white furnace (a Lambert sphere of albedo 1 in a uniform
// environment is invisible: every pixel is L), and importance sampling of a map with a small bright
// sun against BSDF sampling alone.
#include <gtest/gtest.h>

#include <cmath>

#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

// A uniform map of radiance L, as an image (so that the image's distribution is what is sampled).
EnvironmentLight uniformImage(float radiance,
                              EnvironmentMapping mapping = EnvironmentMapping::Equirectangular) {
    const int height = mapping == EnvironmentMapping::EqualArea ? 8 : 4;
    EnvironmentImage image{8, height, std::vector<Rgb>(size_t(8 * height), Rgb(radiance)), mapping};
    return EnvironmentLight::fromImage(image, Rgb(1.0f), Transform::rotate(30.0f, {1.0f, 0.2f, 0.0f}));
}

// The white furnace. A convex sphere of albedo 1: every path that hits it scatters once and escapes,
// so each pixel's expectation is L, whether its rays hit the sphere or not. Pixels whose rays all
// miss see L exactly. Pixels on the sphere are means of n = 256 samples (a box filter of radius
// 1/2: each sample counts in one pixel with weight 1), each sample an MIS combination bounded by a
// few L; the pixel's own sample variance s^2 gives its standard error s / sqrt(n), and 6 standard
// errors (two-sided normal tail 2e-9 per pixel, 1024 pixels) bound the deviation. The image mean
// is checked more tightly, against its standard error over every sample.
void expectWhiteFurnace(const EnvironmentLight& environment, float radiance, LightStrategy strategy) {
    Scene scene;
    scene.film = {32, 32, 256, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0.0f, 0.0f, 3.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 45.0f;
    scene.integrator.strategy = strategy;
    scene.settings.sampler = SamplerKind::Independent;
    scene.settings.seed = 3;
    scene.materials = {testing::makeLambert(Rgb(1.0f))};
    Sphere sphere;
    sphere.radius = 1.0f;
    scene.spheres.push_back(sphere);
    scene.environment = environment;
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    double sum = 0.0, sumSquares = 0.0, count = 0.0;
    int exactPixels = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const PixelSums& p = film.at(x, y);
            const double n = p.weight, mean = p.radiance[1] / n;
            const double variance = std::max(0.0, double(p.radianceSquared[1]) / n - mean * mean);
            sum += p.radiance[1];
            sumSquares += p.radianceSquared[1];
            count += n;
            if (variance == 0.0) {
                ++exactPixels;
                EXPECT_NEAR(mean, radiance, 1e-6 * radiance) << "pixel " << x << ", " << y;
            } else {
                EXPECT_NEAR(mean, radiance, 6.0 * std::sqrt(variance / n) + 1e-6 * radiance)
                    << "pixel " << x << ", " << y;
            }
        }
    EXPECT_GT(exactPixels, 100);  // the corners miss the sphere
    const double mean = sum / count;
    const double standardError = std::sqrt(std::max(0.0, sumSquares / count - mean * mean) / count);
    EXPECT_NEAR(mean, radiance, 5.0 * standardError + 1e-6 * radiance);
}

TEST(EnvironmentFurnace, UniformImageLambertSphereIsInvisibleMis) {
    expectWhiteFurnace(uniformImage(0.8f), 0.8f, LightStrategy::Mis);
}
TEST(EnvironmentFurnace, UniformImageLambertSphereIsInvisibleLightSampling) {
    expectWhiteFurnace(uniformImage(0.8f), 0.8f, LightStrategy::Light);
}
TEST(EnvironmentFurnace, UniformEqualAreaImageLambertSphereIsInvisible) {
    expectWhiteFurnace(uniformImage(0.8f, EnvironmentMapping::EqualArea), 0.8f, LightStrategy::Mis);
    expectWhiteFurnace(uniformImage(0.8f, EnvironmentMapping::EqualArea), 0.8f, LightStrategy::Light);
}
TEST(EnvironmentFurnace, ConstantLambertSphereIsInvisible) {
    expectWhiteFurnace(EnvironmentLight::constant(Rgb(1.5f)), 1.5f, LightStrategy::Mis);
}

// A floor under a dim sky with a small, bright sun (2 x 2 texels of a 64 x 32 map, 20000 times the
// sky's radiance: most of the floor's irradiance). BSDF sampling finds the sun rarely; sampling
// the map by luminance finds it at every vertex. The mean squared error against a 4096-spp
// reference, over the image at 16 spp, must be at least 10 times lower with importance sampling.
Scene sunScene(LightStrategy strategy, int spp, uint64_t seed) {
    Scene scene;
    scene.film = {24, 24, spp, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0.0f, 3.0f, 3.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 40.0f;
    scene.integrator.strategy = strategy;
    scene.settings.seed = seed;
    scene.materials = {testing::makeLambert(Rgb(0.6f))};
    scene.meshes.push_back(testing::makeQuad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, 0));
    EnvironmentImage image{64, 32, std::vector<Rgb>(64 * 32, Rgb(0.05f, 0.07f, 0.1f))};
    for (int y = 6; y < 8; ++y)
        for (int x = 20; x < 22; ++x) image.texels[size_t(y * 64 + x)] = Rgb(1000.0f, 950.0f, 900.0f);
    scene.environment = EnvironmentLight::fromImage(image, Rgb(1.0f), Transform());
    return scene;
}

std::vector<double> renderGreen(const Scene& scene) {
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    std::vector<double> values;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            values.push_back(film.at(x, y).radiance[1] / film.at(x, y).weight);
    return values;
}

double meanSquaredError(const std::vector<double>& image, const std::vector<double>& reference) {
    double sum = 0.0;
    for (size_t i = 0; i < image.size(); ++i) sum += (image[i] - reference[i]) * (image[i] - reference[i]);
    return sum / double(image.size());
}

TEST(EnvironmentSunImportanceSampling, TenTimesLowerErrorThanBsdfSampling) {
    const std::vector<double> reference = renderGreen(sunScene(LightStrategy::Mis, 4096, 100));
    const double bsdf = meanSquaredError(renderGreen(sunScene(LightStrategy::Bsdf, 16, 1)), reference);
    const double mis = meanSquaredError(renderGreen(sunScene(LightStrategy::Mis, 16, 1)), reference);
    const double light = meanSquaredError(renderGreen(sunScene(LightStrategy::Light, 16, 1)), reference);
    EXPECT_GT(bsdf, 10.0 * mis) << "MSE: BSDF sampling " << bsdf << ", MIS " << mis;
    EXPECT_GT(bsdf, 10.0 * light) << "MSE: BSDF sampling " << bsdf << ", light sampling " << light;
    RecordProperty("mse_bsdf", std::to_string(bsdf));
    RecordProperty("mse_mis", std::to_string(mis));
    std::printf("MSE at 16 spp: BSDF sampling %g, MIS %g, light sampling %g (ratios %.1f, %.1f)\n", bsdf, mis,
                light, bsdf / mis, bsdf / light);
}

}  // namespace
}  // namespace penumbra
