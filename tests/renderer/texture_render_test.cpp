// Textures in renders: a checkerboard on a quad gives exactly the expected colour at sample points
// away from the squares' edges. A Lambert quad under a uniform environment L, rendered with BSDF
// sampling alone and one bounce, has every sample exactly albedo(uv) * L (the cosine-weighted
// sample's weight is the albedo, and every bounce ray escapes to L), so a pixel whose samples all
// fall inside one square is exactly that square's albedo times L.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <utility>

#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

TEST(TextureCheckerboardRender, ExactColoursAwayFromEdges) {
    const Rgb a(0.8f, 0.3f, 0.1f), b(0.1f, 0.5f, 0.9f);
    const float radiance = 2.0f;
    const int size = 64, squares = 8;  // 8 x 8 squares of 8 x 8 pixels each
    Scene scene;
    scene.film = {size, size, 16, FilterKind::Box, 0.5f};
    // A quad of side 2 at z = 0, filling the view exactly: fov with tan(fov / 2) = 1 / distance.
    const float distance = 4.0f;
    scene.camera.lookFrom = {0.0f, 0.0f, distance};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 2.0f * std::atan(1.0f / distance) * 180.0f / kPi;
    scene.integrator.strategy = LightStrategy::Bsdf;
    scene.integrator.maxDepth = 1;
    Texture checker = Texture::checkerboard(a, b);
    checker.mapUv({float(squares), float(squares)}, {0.0f, 0.0f});
    scene.materials = {Material(
        Lambert{}, true, {{checker, [](MaterialModel& m, Rgb c) { std::get<Lambert>(m).albedo = c; }}})};
    // uv (0, 0) at the bottom-left corner, u to the right, v up.
    TriangleMesh quad = testing::makeQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0);
    quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    scene.meshes.push_back(quad);
    scene.environment = EnvironmentLight::constant(Rgb(radiance));
    Film film(size, size);
    render(scene, RenderOptions{}, film);
    const int cell = size / squares;
    int checked = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            // Pixels next to a square's edge may mix the two colours (and the quad's own edge).
            if (x % cell == 0 || x % cell == cell - 1 || y % cell == 0 || y % cell == cell - 1) continue;
            const int column = x / cell, row = (size - 1 - y) / cell;  // raster y runs down, v up
            const Rgb expected = ((column + row) % 2 == 0 ? a : b) * radiance;
            const PixelSums& p = film.at(x, y);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p.radiance[c] / p.weight, expected[c], 1e-6 * expected[c])
                    << "pixel " << x << ", " << y;
            ++checked;
        }
    EXPECT_EQ(checked, squares * squares * (cell - 2) * (cell - 2));
}

// Textured emission seen directly: a checkerboard-emitting quad filling the view, max depth 0.
TEST(TextureEmissionRender, ExactRadianceAwayFromEdges) {
    const Rgb a(3.0f, 1.0f, 0.5f), b(0.25f, 0.5f, 2.0f);
    const int size = 32, squares = 4;
    Scene scene;
    scene.film = {size, size, 8, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0.0f, 0.0f, 4.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 2.0f * std::atan(1.0f / 4.0f) * 180.0f / kPi;
    scene.integrator.maxDepth = 0;
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    TriangleMesh quad = testing::makeQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 0);
    quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    Texture checker = Texture::checkerboard(a, b);
    checker.mapUv({float(squares), float(squares)}, {0.0f, 0.0f});
    quad.emission.texture = std::make_shared<const Texture>(checker);
    quad.emission.radiance = (a + b) * 0.5f;
    scene.meshes.push_back(quad);
    Film film(size, size);
    render(scene, RenderOptions{}, film);
    const int cell = size / squares;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            if (x % cell == 0 || x % cell == cell - 1 || y % cell == 0 || y % cell == cell - 1) continue;
            const int column = x / cell, row = (size - 1 - y) / cell;
            const Rgb expected = (column + row) % 2 == 0 ? a : b;
            const PixelSums& p = film.at(x, y);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p.radiance[c] / p.weight, expected[c], 1e-6 * expected[c])
                    << "pixel " << x << ", " << y;
        }
}

// A floor lit by a checkerboard-emitting panel: light sampling (which looks the texture up at the
// point it samples) and BSDF sampling (at the point it hits) estimate the same image. Image means
// within 5 combined standard errors.
TEST(TextureEmissionRender, LightAndBsdfSamplingAgree) {
    auto renderMean = [](LightStrategy strategy) {
        Scene scene;
        scene.film = {24, 24, 256, FilterKind::Box, 0.5f};
        scene.camera.lookFrom = {0.0f, 2.0f, 3.0f};
        scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
        scene.integrator.maxDepth = 1;
        scene.integrator.strategy = strategy;
        scene.settings.sampler = SamplerKind::Independent;
        scene.materials = {testing::makeLambert(Rgb(0.7f)), testing::makeLambert(Rgb(0.0f))};
        scene.meshes.push_back(testing::makeQuad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, 0));
        TriangleMesh panel = testing::makeQuad({-1, 1.5f, -1}, {2, 0, 0}, {0, 0, 2}, 1);  // faces down
        panel.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        Texture checker = Texture::checkerboard(Rgb(8.0f, 2.0f, 1.0f), Rgb(0.0f, 1.0f, 6.0f));
        checker.mapUv({3.0f, 3.0f}, {0.0f, 0.0f});
        panel.emission.texture = std::make_shared<const Texture>(checker);
        panel.emission.radiance = Rgb(4.0f, 1.5f, 3.5f);
        scene.meshes.push_back(panel);
        Film film(24, 24);
        render(scene, RenderOptions{}, film);
        double sum = 0, sumSquares = 0, count = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                sum += film.at(x, y).radiance[2];
                sumSquares += film.at(x, y).radianceSquared[2];
                count += film.at(x, y).weight;
            }
        const double mean = sum / count;
        return std::pair<double, double>{mean, std::max(0.0, sumSquares / count - mean * mean) / count};
    };
    const auto [light, lightVariance] = renderMean(LightStrategy::Light);
    const auto [bsdf, bsdfVariance] = renderMean(LightStrategy::Bsdf);
    EXPECT_GT(light, 0.01);
    EXPECT_NEAR(light, bsdf, 5.0 * std::sqrt(lightVariance + bsdfVariance));
}

}  // namespace
}  // namespace penumbra
