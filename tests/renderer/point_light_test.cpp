// A point light of intensity I at height h over a Lambert plane of albedo a. The radiance leaving
// the plane at a point at distance d from the light, with incidence cosine cos = h / d, is
//   L = (a / pi) * I * cos / d^2.
// A camera with a very narrow field of view looks straight down at chosen points; over its
// footprint (+-0.44% of the height) L varies by under 1%, and symmetrically, so the pixel mean
// equals the centre value to about 1e-5 relative.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/sampling.h"
#include "tests/support/rendered_mean.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

using testing::renderedMeanAt;

TEST(PointLight, LambertPlaneMatchesClosedFormIrradiance) {
    const float albedo = 0.6f, intensity = 25.0f, height = 2.0f;
    Scene scene;
    scene.film = {8, 8, 16, FilterKind::Box, 0.5f};
    scene.camera.verticalFovDegrees = 0.5f;
    scene.materials = {testing::makeLambert(Rgb(albedo))};
    scene.meshes.push_back(testing::makeQuad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, 0));
    scene.lights.push_back(PointLight{{0.0f, height, 0.0f}, Rgb(intensity)});
    scene.integrator.maxDepth = 1;

    for (float offset : {0.0f, 1.0f, 2.0f, 3.5f}) {
        const Vec3f target{offset, 0.0f, 0.0f};
        const double distanceSquared = double(offset) * offset + double(height) * height;
        const double cosine = height / std::sqrt(distanceSquared);
        const double expected = albedo / kPi * intensity * cosine / distanceSquared;
        EXPECT_NEAR(renderedMeanAt(target, scene), expected, 2e-4 * expected) << "offset " << offset;
    }
}

TEST(PointLight, NothingReachesThePlaneFromBelow) {
    Scene scene;
    scene.film = {8, 8, 4, FilterKind::Box, 0.5f};
    scene.camera.verticalFovDegrees = 10.0f;
    scene.materials = {testing::makeLambert(Rgb(0.6f))};
    scene.meshes.push_back(testing::makeQuad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, 0));
    scene.lights.push_back(PointLight{{0.0f, -2.0f, 0.0f}, Rgb(25.0f)});  // under the plane
    EXPECT_EQ(renderedMeanAt({0.0f, 0.0f, 0.0f}, scene), 0.0);
}

// A spot light of axis intensity I at height h pointing straight down, cone 30 degrees with a
// 10-degree falloff band: L = (a / pi) I f(cos) cos / d^2 with f 1 inside 20 degrees, pbrt-v4's
// smoothstep in cos between 20 and 30 (written out here), 0 beyond. The band's point is where the
// smoothstep's second derivative vanishes (t = 1/2), so that the camera's footprint averages to
// the centre value as for the point light.
TEST(SpotLight, LambertPlaneMatchesClosedFormInsideTheBandAndOutside) {
    const float albedo = 0.6f, intensity = 25.0f, height = 2.0f;
    const double cosEnd = std::cos(30.0 * kPi / 180.0), cosStart = std::cos(20.0 * kPi / 180.0);
    Scene scene;
    scene.film = {8, 8, 16, FilterKind::Box, 0.5f};
    scene.camera.verticalFovDegrees = 0.5f;
    scene.materials = {testing::makeLambert(Rgb(albedo))};
    scene.meshes.push_back(testing::makeQuad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, 0));
    scene.lights.push_back(
        SpotLight{{0.0f, height, 0.0f}, {0.0f, -1.0f, 0.0f}, Rgb(intensity), float(cosStart), float(cosEnd)});
    scene.integrator.maxDepth = 1;
    const double bandMiddle = std::tan(std::acos(0.5 * (cosStart + cosEnd))) * height;
    for (double offset : {0.0, 0.5, bandMiddle, 1.5, 3.0}) {
        const double distanceSquared = offset * offset + double(height) * height;
        const double cosine = height / std::sqrt(distanceSquared);
        const double t = std::clamp((cosine - cosEnd) / (cosStart - cosEnd), 0.0, 1.0);
        const double expected =
            albedo / kPi * intensity * (t * t * (3.0 - 2.0 * t)) * cosine / distanceSquared;
        const double found = renderedMeanAt({float(offset), 0.0f, 0.0f}, scene);
        if (offset == bandMiddle) {
            EXPECT_NEAR(t, 0.5, 1e-9);
        }
        if (expected == 0.0)
            EXPECT_EQ(found, 0.0) << "offset " << offset;
        else
            EXPECT_NEAR(found, expected, 2e-4 * expected) << "offset " << offset;
    }
}

// The power that chooses between lights: the falloff integrated over the sphere, against a
// midpoint quadrature in cos(theta).
TEST(SpotLight, SolidAngleIsTheFalloffsIntegral) {
    for (auto [angle, delta] :
         {std::pair{30.0, 5.0}, {30.0, 0.0}, {90.0, 45.0}, {180.0, 180.0}, {10.0, 10.0}}) {
        SpotLight spot;
        spot.cosFalloffEnd = float(std::cos(angle * kPi / 180.0));
        spot.cosFalloffStart = float(std::cos((angle - delta) * kPi / 180.0));
        const int steps = 200000;
        double integral = 0.0;
        for (int i = 0; i < steps; ++i) integral += spot.falloff(float(-1.0 + 2.0 * (i + 0.5) / steps));
        integral *= 2.0 * kPi * 2.0 / steps;  // d omega = 2 pi d cos(theta)
        EXPECT_NEAR(spot.solidAngle(), integral, 1e-4 * integral) << angle << " " << delta;
    }
}

// A directional light of irradiance E arriving at angle theta from the normal gives a Lambert
// plane the radiance (a / pi) E cos(theta) everywhere, and an occluder a sharp shadow.
TEST(DirectionalLight, LambertPlaneMatchesClosedForm) {
    const float albedo = 0.6f, irradiance = 3.0f;
    for (float degrees : {0.0f, 30.0f, 60.0f}) {
        Scene scene;
        scene.film = {8, 8, 4, FilterKind::Box, 0.5f};
        scene.camera.verticalFovDegrees = 5.0f;
        scene.materials = {testing::makeLambert(Rgb(albedo))};
        scene.meshes.push_back(testing::makeQuad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, 0));
        const float theta = degrees * kPi / 180.0f;
        scene.lights.push_back(DirectionalLight{{std::sin(theta), -std::cos(theta), 0.0f}, Rgb(irradiance)});
        scene.integrator.maxDepth = 1;
        const double expected = albedo / kPi * irradiance * std::cos(theta);
        EXPECT_NEAR(renderedMeanAt({1.0f, 0.0f, 2.0f}, scene), expected, 1e-4 * expected)
            << degrees << " degrees";
        // A small occluder up-light of the target casts a hard shadow on it (for oblique light, so
        // that the camera looking straight down does not see the occluder itself).
        if (degrees == 0.0f) continue;
        scene.spheres.push_back(
            {"blocker",
             Vec3f{1.0f, 0.0f, 2.0f} + Vec3f{-std::sin(theta), std::cos(theta), 0.0f} * 0.5f,
             0.2f,
             0,
             {},
             {}});
        EXPECT_EQ(renderedMeanAt({1.0f, 0.0f, 2.0f}, scene), 0.0) << degrees << " degrees, shadowed";
    }
}

}  // namespace
}  // namespace penumbra
