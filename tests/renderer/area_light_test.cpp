// Soft shadows against closed forms. A Lambert floor of albedo a reflects L_o = a E / pi, where E
// is the irradiance from the area light. A camera with a very narrow field of view looks at one
// floor point from the side (below the light and the occluder), so the pixel values measure E at
// that point.
//  - disk light of radius R at height h, centred above the point: E = pi L sin^2(theta),
//    sin^2(theta) = R^2 / (R^2 + h^2);
//  - sphere light of radius R, centre at distance D straight above: E = pi L (R / D)^2;
//  - a rectangular light partly hidden by the straight edge of an occluder: the visible part of
//    the light is a rectangle, whose irradiance is given exactly by Lambert's formula for
//    polygonal luminaires, E = L / 2 * sum_i angle_i * (n . unit(v_i x v_i+1)).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

constexpr float kAlbedo = 0.5f;

struct Measurement {
    double mean;
    double standardError;
};

// Renders the floor point `target` seen from `eye` and returns the irradiance implied by the
// pixels, E = pi L_o / a, with its standard error from the film's sums of squares.
Measurement measureIrradiance(Scene scene, Vec3f target, Vec3f eye) {
    scene.film = {8, 8, 1024, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = eye;
    scene.camera.lookAt = target;
    scene.camera.verticalFovDegrees = 0.05f;
    // The error estimate below treats samples as independent; for the stratified sampler it is an
    // over-estimate, so tolerances built on it are conservative.
    scene.integrator.maxDepth = 1;
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    double sum = 0, sumSquares = 0, count = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            sum += film.at(x, y).radiance[1];
            sumSquares += film.at(x, y).radianceSquared[1];
            count += film.at(x, y).weight;
        }
    const double mean = sum / count;
    const double variance = std::max(0.0, sumSquares / count - mean * mean);
    const double toIrradiance = kPi / kAlbedo;
    return {mean * toIrradiance, std::sqrt(variance / count) * toIrradiance};
}

Scene floorScene() {
    Scene scene;
    scene.materials = {testing::makeLambert(Rgb(kAlbedo)), testing::makeLambert(Rgb(0.0f))};
    scene.meshes.push_back(testing::makeQuad({-20, 0, -20}, {0, 0, 40}, {40, 0, 0}, 0));  // faces +y
    return scene;
}

// Within 1%, or within 5 standard errors where the noise is larger (deep in the penumbra most
// light samples are blocked); the noise itself must stay small enough for the test to have power.
void expectIrradiance(const Measurement& m, double expected, const char* what) {
    EXPECT_LT(m.standardError, 0.02 * expected) << what;
    EXPECT_NEAR(m.mean, expected, std::max(0.01 * expected, 5.0 * m.standardError)) << what;
}

TEST(AreaLight, DiskIrradianceIsPiLSinSquared) {
    const float radiance = 3.0f, radius = 0.6f, height = 1.0f;
    Scene scene = floorScene();
    TriangleMesh disk;
    const int segments = 256;
    disk.positions.push_back({0.0f, height, 0.0f});
    for (int i = 0; i < segments; ++i) {
        const double angle = 2.0 * kPi * i / segments;
        disk.positions.push_back({radius * float(std::cos(angle)), height, radius * float(std::sin(angle))});
        // Wound so the front faces -y (down, towards the floor).
        disk.indices.insert(disk.indices.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % segments)});
    }
    disk.material = 1;
    disk.emission.radiance = Rgb(radiance);
    scene.meshes.push_back(disk);
    // A 256-gon inscribed in the disk has area fraction sin(2 pi / 256) / (2 pi / 256) = 0.99990.
    const double sin2 = radius * radius / (radius * radius + height * height);
    const double expected = kPi * radiance * sin2 * (std::sin(2 * kPi / segments) / (2 * kPi / segments));
    expectIrradiance(measureIrradiance(scene, {0, 0, 0}, {1.5f, 0.4f, 0.3f}), expected, "disk light");
}

TEST(AreaLight, SphereIrradianceIsPiLSinSquared) {
    const float radiance = 2.0f, radius = 0.3f, distance = 1.2f;
    Scene scene = floorScene();
    Sphere light;
    light.center = {0.0f, distance, 0.0f};
    light.radius = radius;
    light.material = 1;
    light.emission.radiance = Rgb(radiance);
    scene.spheres.push_back(light);
    const double expected = kPi * radiance * (radius / distance) * (radius / distance);
    expectIrradiance(measureIrradiance(scene, {0, 0, 0}, {1.5f, 0.4f, 0.3f}), expected, "sphere light");
}

// Lambert's formula: irradiance at the origin (normal +y) from a polygon of radiance L.
double polygonIrradiance(const std::vector<Vec3f>& polygon, double radiance) {
    double sum = 0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const Vec3f a = normalize(polygon[i]), b = normalize(polygon[(i + 1) % polygon.size()]);
        const double angle = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
        sum += angle * normalize(cross(a, b)).y;
    }
    return radiance / 2.0 * std::abs(sum);
}

TEST(AreaLight, PenumbraLiesWhereTheGeometrySays) {
    // Light: x in [-w/2, w/2], z in [-d/2, d/2] at height H, facing down. Occluder: the half-plane
    // x < 0 at height ho. From floor point x_f the light is visible for x_l >= x_f (1 - H / ho):
    // umbra for x_f <= -(w/2) / (H/ho - 1), fully lit for x_f >= (w/2) / (H/ho - 1).
    const float radiance = 4.0f, width = 0.8f, depth = 0.8f, lightHeight = 1.5f, occluderHeight = 0.75f;
    Scene scene = floorScene();
    TriangleMesh light =
        testing::makeQuad({-width / 2, lightHeight, -depth / 2}, {width, 0, 0}, {0, 0, depth}, 1);
    light.emission.radiance = Rgb(radiance);
    scene.meshes.push_back(light);
    scene.meshes.push_back(testing::makeQuad({-20, occluderHeight, -20}, {20, 0, 0}, {0, 0, 40}, 1));

    const float edge = (width / 2) / (lightHeight / occluderHeight - 1.0f);  // penumbra half-width: 0.4
    for (float xf : {-0.6f, -0.35f, -0.2f, 0.0f, 0.15f, 0.3f, 0.38f, 0.6f}) {
        const float visibleFrom =
            std::clamp(xf * (1.0f - lightHeight / occluderHeight), -width / 2, width / 2);
        double expected = 0.0;
        if (visibleFrom < width / 2) {
            // The visible rectangle, relative to the floor point.
            const std::vector<Vec3f> polygon = {{visibleFrom - xf, lightHeight, -depth / 2},
                                                {width / 2 - xf, lightHeight, -depth / 2},
                                                {width / 2 - xf, lightHeight, depth / 2},
                                                {visibleFrom - xf, lightHeight, depth / 2}};
            expected = polygonIrradiance(polygon, radiance);
        }
        const Measurement m = measureIrradiance(scene, {xf, 0, 0}, {xf + 0.2f, 0.3f, -1.5f});
        if (xf <= -edge) {
            EXPECT_EQ(m.mean, 0.0) << "umbra at x = " << xf;
        } else {
            expectIrradiance(m, expected, "penumbra / lit");
        }
    }
}

// Several emitters, so that next-event estimation chooses among them at the vertex
// (LightSet::choose), under MIS with the BSDF samples that find the same lights: a quad overhead,
// a quad standing beside the point facing it, a sphere light and a point light. The irradiance is
// the sum of their closed forms (Lambert's formula for the quads, pi L (R / D)^2 cos(theta) for
// a sphere above the horizon, I cos(theta) / d^2 for the point light).
TEST(AreaLight, LightsChosenAtTheVertexSumToTheirClosedForms) {
    Scene scene = floorScene();
    TriangleMesh overhead =
        testing::makeQuad({-0.5f, 1.0f, -0.4f}, {0.8f, 0, 0}, {0, 0, 0.8f}, 1);  // faces -y
    overhead.emission.radiance = Rgb(3.0f);
    TriangleMesh beside = testing::makeQuad({1.0f, 0.2f, -0.5f}, {0, 0, 1.0f}, {0, 0.8f, 0}, 1);  // faces -x
    beside.emission.radiance = Rgb(2.0f);
    scene.meshes.push_back(overhead);
    scene.meshes.push_back(beside);
    Sphere sphere;
    sphere.center = {-1.0f, 0.8f, 0.5f};
    sphere.radius = 0.2f;
    sphere.material = 1;
    sphere.emission.radiance = Rgb(5.0f);
    scene.spheres.push_back(sphere);
    const Vec3f pointPosition{0.8f, 1.5f, -0.8f};
    scene.lights.push_back(PointLight{pointPosition, Rgb(1.0f)});

    const double quads =
        polygonIrradiance(
            {{-0.5f, 1.0f, -0.4f}, {0.3f, 1.0f, -0.4f}, {0.3f, 1.0f, 0.4f}, {-0.5f, 1.0f, 0.4f}}, 3.0) +
        polygonIrradiance({{1.0f, 0.2f, -0.5f}, {1.0f, 0.2f, 0.5f}, {1.0f, 1.0f, 0.5f}, {1.0f, 1.0f, -0.5f}},
                          2.0);
    const double sphereDistance = length(sphere.center);
    const double sphereIrradiance =
        kPi * 5.0 * std::pow(sphere.radius / sphereDistance, 2) * (sphere.center.y / sphereDistance);
    const double pointIrradiance = pointPosition.y / std::pow(double(length(pointPosition)), 3);
    expectIrradiance(measureIrradiance(scene, {0, 0, 0}, {0.3f, 0.4f, 1.5f}),
                     quads + sphereIrradiance + pointIrradiance, "four emitters chosen at the vertex");
}

}  // namespace
}  // namespace penumbra
