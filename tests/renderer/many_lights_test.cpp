// Many lights through the path tracer: next-event estimation choosing through the light tree
// (lights/light_tree.h) against choosing by power (`"light_sampler": "power"`).
//  - 300 point lights over a Lambert plane of albedo a: the radiance leaving a point x is
//    (a / pi) sum_i I_i cos(theta_i) / d_i^2 (closed form); both samplers render it within 5
//    standard errors (measured from the pixels' spread: box filter, so pixels are independent),
//    and the tree's standard error is at most a third of power's at the same samples.
//  - 120 emitting quads above the plane: no closed form, but both samplers estimate the same image
//    (MIS weighs BSDF hits by LightSet's choice probability, which the tree changes), so their
//    means agree within 5 combined standard errors, the tree's again with less noise.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"
#include "tests/support/rendered_mean.h"

namespace penumbra {
namespace {

using testing::MeanEstimate;
using testing::renderedMeanAndErrorAt;  // the narrow field of view's footprint: +-0.44% of the height

std::string sceneHeader(const std::string& lightSampler) {
    return R"({
        "film": {"resolution": [16, 16], "spp": 16, "filter": {"type": "box", "radius": 0.5}},
        "camera": {"fov": 0.5},
        "integrator": {"max_depth": 1, "light_sampler": ")" +
           lightSampler + R"("},
        "materials": {"white": {"type": "lambert", "albedo": 0.5}, "black": {"type": "lambert", "albedo": 0}},
)";
}

constexpr const char* kPlane =
    R"({"type": "quad", "corner": [-50, 0, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0], "material": "white"})";

TEST(ManyLights, PointLightsRenderTheirClosedFormWithLessNoiseThroughTheTree) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    struct Light {
        Vec3f position;
        float intensity;
    };
    std::vector<Light> lights;
    std::string lightsJson;
    for (int i = 0; i < 300; ++i) {
        const Light l{{-5.0f + 10.0f * u(rng), 0.5f + 1.5f * u(rng), -5.0f + 10.0f * u(rng)},
                      0.5f + 2.5f * u(rng)};
        lights.push_back(l);
        lightsJson += (i ? ", " : "") + std::string(R"({"type": "point", "position": [)") +
                      std::to_string(l.position.x) + ", " + std::to_string(l.position.y) + ", " +
                      std::to_string(l.position.z) + R"(], "intensity": )" + std::to_string(l.intensity) +
                      "}";
    }
    for (const Vec3f target : {Vec3f{0.3f, 0.0f, -0.2f}, Vec3f{4.0f, 0.0f, 4.5f}}) {
        double expected = 0.0;
        for (const Light& l : lights) {
            // The JSON's decimal positions, as the scene reads them.
            const Vec3f position{std::stof(std::to_string(l.position.x)),
                                 std::stof(std::to_string(l.position.y)),
                                 std::stof(std::to_string(l.position.z))};
            const Vec3f d = position - target;
            const double distanceSquared = lengthSquared(d);
            expected += 0.5 / kPi * std::stof(std::to_string(l.intensity)) *
                        (d.y / std::sqrt(distanceSquared)) / distanceSquared;
        }
        MeanEstimate estimates[2];
        for (int s = 0; s < 2; ++s) {
            const std::string json = sceneHeader(s == 0 ? "bvh" : "power") + R"("shapes": [)" + kPlane +
                                     R"(], "lights": [)" + lightsJson + "]}";
            estimates[s] = renderedMeanAndErrorAt(target, parseScene(json, "many-point-lights.json"));
            EXPECT_NEAR(estimates[s].mean, expected, 5.0 * estimates[s].standardError)
                << (s == 0 ? "bvh" : "power") << " at x " << target.x;
        }
        EXPECT_LT(estimates[0].standardError, estimates[1].standardError / 3.0)
            << "bvh " << estimates[0].standardError << ", power " << estimates[1].standardError;
    }
}

TEST(ManyLights, EmittingQuadsRenderTheSameImageWithEitherSampler) {
    std::mt19937 rng(32);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::string quads;
    for (int i = 0; i < 120; ++i) {
        const float x = -4.0f + 8.0f * u(rng), y = 0.3f + 1.5f * u(rng), z = -4.0f + 8.0f * u(rng);
        const float size = 0.05f + 0.2f * u(rng), radiance = 1.0f + 9.0f * u(rng);
        // Facing down (edge2 x edge1 along -y), black so that light does not bounce off them.
        quads += R"(, {"type": "quad", "corner": [)" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                 std::to_string(z) + R"(], "edge1": [)" + std::to_string(size) +
                 R"(, 0, 0], "edge2": [0, 0, )" + std::to_string(size) +
                 R"(], "material": "black", "emission": {"radiance": )" + std::to_string(radiance) + "}}";
    }
    for (const Vec3f target : {Vec3f{0.2f, 0.0f, 0.1f}, Vec3f{-3.0f, 0.0f, 2.0f}}) {
        MeanEstimate estimates[2];
        for (int s = 0; s < 2; ++s) {
            const std::string json =
                sceneHeader(s == 0 ? "bvh" : "power") + R"("shapes": [)" + kPlane + quads + "]}";
            estimates[s] = renderedMeanAndErrorAt(target, parseScene(json, "many-quads.json"));
        }
        const double combined = std::hypot(estimates[0].standardError, estimates[1].standardError);
        EXPECT_GT(estimates[0].mean, 0.0);
        EXPECT_NEAR(estimates[0].mean, estimates[1].mean, 5.0 * combined) << "at x " << target.x;
        EXPECT_LT(estimates[0].standardError, estimates[1].standardError / 2.0)
            << "bvh " << estimates[0].standardError << ", power " << estimates[1].standardError;
    }
}

}  // namespace
}  // namespace penumbra
