// Layered materials (materials/layered_bsdf.h) in the path tracer, read from the scene format: a
// plane under a uniform sky of radiance 1, seen from theta, shows its directional albedo. The
// integrator combines light sampling (eval, the pdf estimate) with BSDF sampling (sample) by
// multiple importance sampling, so this checks that the three estimators fit together:
//   - a smooth coat over a Lambertian base (coated_diffuse, model layered, a clear thin slab):
//     the closed form F + (1 - F) rho (1 - F_int) / (1 - rho F_int);
//   - a rough coat over a rough conductor (coated_conductor, an absorbing slab): the mean weight
//     of the model's own sample(), an estimator that uses neither eval nor the pdf.
// Tolerance: 5 standard errors of the pixels' mean (and of the reference's, where it has one).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "materials/fresnel.h"
#include "materials/material.h"
#include "scenes/scene_loader.h"
#include "tests/support/pixel_mean.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

Scene planeUnderSky(double thetaDegrees, const std::string& material) {
    const double t = thetaDegrees * M_PI / 180.0;
    const std::string from =
        std::to_string(0.3 + 5.0 * std::sin(t)) + ", 0.2, " + std::to_string(5.0 * std::cos(t));
    return parseScene(R"({
        "film": {"resolution": [16, 16], "spp": 256, "filter": {"type": "box"}},
        "integrator": {"max_depth": 4},
        "background": 1,
        "camera": {"look_from": [)" +
                          from +
                          R"(], "look_at": [0.3, 0.2, 0], "fov": 0.005},
        "materials": {"coated": )" +
                          material + R"(},
        "shapes": [{"type": "triangle_mesh", "material": "coated",
                    "positions": [[-100, -100, 0], [100, -100, 0], [100, 100, 0], [-100, 100, 0]],
                    "indices": [0, 1, 2, 0, 2, 3]}]})",
                      "scene.json");
}

TEST(LayeredRender, SmoothCoatOverLambertReflectsTheClosedFormAlbedo) {
    const float eta = 1.5f;
    const Rgb rho{0.8f, 0.5f, 0.2f};
    const double fInt = diffuseFresnelReflectance(1.0 / eta);
    for (const double theta : {0.0, 60.0}) {
        const Scene scene = planeUnderSky(theta, R"({"type": "coated_diffuse", "model": "layered",
            "albedo": [0.8, 0.5, 0.2], "eta": 1.5, "thickness": 0, "max_depth": 100})");
        const double F = fresnelDielectric(float(std::cos(theta * M_PI / 180.0)), eta);
        for (int c = 0; c < 3; ++c) {
            const double expected = F + (1.0 - F) * rho[c] * (1.0 - fInt) / (1.0 - rho[c] * fInt);
            const testing::PixelMean mean = testing::renderedChannelMean(scene, c);
            EXPECT_TRUE(test::withinSigmas(mean.mean, expected, mean.standardError))
                << "theta " << theta << ", channel " << c;
        }
    }
}

TEST(LayeredRender, RoughCoatOverRoughMetalReflectsWhatItSamples) {
    for (const double theta : {20.0, 70.0}) {
        const Scene scene = planeUnderSky(theta, R"({"type": "coated_conductor", "alpha": 0.15, "eta": 1.5,
            "conductor": {"eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 1.8], "alpha": 0.3}, "thickness": 0.05})");
        const Material& material = scene.materials.at(0);
        const Vec3f wo{float(std::sin(theta * M_PI / 180.0)), 0.0f, float(std::cos(theta * M_PI / 180.0))};
        test::UniformRng rng(5);
        const int n = 400000;
        for (int c = 0; c < 3; ++c) {
            double sum = 0, sumSquares = 0;
            for (int i = 0; i < n; ++i) {
                const float uLobe = rng.next();
                const std::optional<BsdfSample> s = material.sample(wo, uLobe, rng.next2D(), true);
                const double w = s ? s->weight[c] : 0.0;
                sum += w, sumSquares += w * w;
            }
            const double expected = sum / n;
            const double expectedError = std::sqrt((sumSquares / n - expected * expected) / (n - 1));
            const testing::PixelMean mean = testing::renderedChannelMean(scene, c);
            EXPECT_TRUE(
                test::withinSigmas(mean.mean, expected, std::hypot(mean.standardError, expectedError)))
                << "theta " << theta << ", channel " << c;
        }
    }
}

}  // namespace
}  // namespace penumbra
