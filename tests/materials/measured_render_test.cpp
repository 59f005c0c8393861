// A measured BRDF of our own writing, rendered: a plane of tabulated rough gold (GGX of alpha 0.3,
// tests/support/rgl_bsdf_writer.h) under a uniform sky of radiance 1 shows, seen from theta, the
// analytic BRDF's directional albedo at theta (integrated independently of the tables,
// tests/support/bsdf_test_support.h). Tolerance: 5 standard errors of the pixels' mean plus 1% for
// the tabulation (measured_bsdf_test.cpp bounds its albedo error by that).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "scenes/scene_loader.h"
#include "tests/support/bsdf_test_support.h"
#include "tests/support/pixel_mean.h"
#include "tests/support/rgl_bsdf_writer.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

TEST(MeasuredRender, APlaneOfTabulatedGoldReflectsTheAnalyticAlbedoOfASky) {
    RoughConductor gold;
    gold.eta = {0.143f, 0.374f, 1.442f};
    gold.k = {3.983f, 2.385f, 1.603f};
    gold.distribution = MicrofacetDistribution{0.3f, 0.3f, MicrofacetKind::Ggx};
    const std::string path = ::testing::TempDir() + "/penumbra-measured-render-gold.bsdf";
    {
        std::ofstream out(path, std::ios::binary);
        out << test::tabulateIsotropicGgxBrdf(
            0.3f, [&](Vec3f wo, Vec3f wi) { return gold.eval(wo, wi, true) * wi.z; });
    }
    for (const double theta : {0.0, 45.0, 75.0}) {
        const double t = theta * M_PI / 180.0;
        const std::string from =
            std::to_string(0.3 + 5.0 * std::sin(t)) + ", 0.2, " + std::to_string(5.0 * std::cos(t));
        const Scene scene = parseScene(R"({
            "film": {"resolution": [16, 16], "spp": 256, "filter": {"type": "box"}},
            "integrator": {"max_depth": 4},
            "background": 1,
            "camera": {"look_from": [)" + from +
                                           R"(], "look_at": [0.3, 0.2, 0], "fov": 0.005},
            "materials": {"gold": {"type": "measured", "filename": ")" +
                                           path + R"("}},
            "shapes": [{"type": "triangle_mesh", "material": "gold",
                        "positions": [[-100, -100, 0], [100, -100, 0], [100, 100, 0], [-100, 100, 0]],
                        "indices": [0, 1, 2, 0, 2, 3]}]})",
                                       "scene.json");
        const Rgb expected =
            test::directionalAlbedo(Material(gold), {float(std::sin(t)), 0.0f, float(std::cos(t))});
        for (int c = 0; c < 3; ++c) {
            const testing::PixelMean mean = testing::renderedChannelMean(scene, c);
            EXPECT_TRUE(
                test::withinSigmas(mean.mean, expected[c], mean.standardError + 0.01 * expected[c] / 5.0))
                << "theta " << theta << ", channel " << c;
        }
    }
}

}  // namespace
}  // namespace penumbra
