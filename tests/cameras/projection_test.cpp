// The projections against their closed forms: a small emitter in a known direction lands on the
// pixel the projection's formula (written out here, independently of cameras/) predicts, on both
// backends; a spherical image of an environment is the environment map itself (the two mappings
// agree with the environment light's); a fisheye is black beyond its reach.
#include <gtest/gtest.h>

#include <cmath>

#include "cameras/camera.h"
#include "core/hash.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

constexpr float kDegree = kPi / 180.0f;

// A camera at the origin looking down -z with +y up: its right is +x, so camera space is world
// space with z negated.
CameraParams cameraAtOrigin(CameraProjection projection) {
    CameraParams camera;
    camera.lookFrom = {0.0f, 0.0f, 0.0f};
    camera.lookAt = {0.0f, 0.0f, -1.0f};
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.projection = projection;
    return camera;
}

// The world direction at `azimuth` to the right of the view and `elevation` above it.
Vec3f worldDirection(float azimuthDegrees, float elevationDegrees) {
    const float a = azimuthDegrees * kDegree, e = elevationDegrees * kDegree;
    return {std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)};
}

struct Centroid {
    double x = 0, y = 0, total = 0;
};

// Renders emitting spheres of angular radius ~`radius` / distance at `positions` (black
// elsewhere, direct light only) and returns the film.
Film renderEmitters(const CameraParams& camera, int width, int height, const std::vector<Vec3f>& positions,
                    float radius, AcceleratorKind accelerator) {
    Scene scene;
    scene.film = {width, height, 64, FilterKind::Box, 0.5f};
    scene.camera = camera;
    scene.integrator.maxDepth = 0;
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    for (const Vec3f& p : positions) {
        Sphere sphere;
        sphere.center = p;
        sphere.radius = radius;
        sphere.emission.radiance = Rgb(1.0f);
        scene.spheres.push_back(sphere);
    }
    Film film(width, height);
    RenderOptions options;
    options.accelerator = accelerator;
    render(scene, options, film);
    return film;
}

// The centroid of the light within `window` pixels of (cx, cy).
Centroid centroidNear(const Film& film, double cx, double cy, int window) {
    Centroid c;
    for (int y = std::max(0, int(cy) - window); y < std::min(film.height(), int(cy) + window + 1); ++y)
        for (int x = std::max(0, int(cx) - window); x < std::min(film.width(), int(cx) + window + 1); ++x) {
            const double v = film.at(x, y).mean().g;
            c.total += v;
            c.x += v * (x + 0.5);
            c.y += v * (y + 0.5);
        }
    if (c.total > 0) {
        c.x /= c.total;
        c.y /= c.total;
    }
    return c;
}

// Each emitter's light is centred on its predicted raster position, on both backends.
void expectEmittersAt(const CameraParams& camera, int width, int height, const std::vector<Vec3f>& positions,
                      const std::vector<Vec2f>& predicted, float radius, double tolerancePixels) {
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        const Film film = renderEmitters(camera, width, height, positions, radius, accelerator);
        for (size_t i = 0; i < positions.size(); ++i) {
            const Centroid c = centroidNear(film, predicted[i].x, predicted[i].y, 6);
            EXPECT_GT(c.total, 0.0) << "emitter " << i << " not found near its predicted pixel";
            EXPECT_NEAR(c.x, predicted[i].x, tolerancePixels) << "emitter " << i;
            EXPECT_NEAR(c.y, predicted[i].y, tolerancePixels) << "emitter " << i;
        }
    }
}

TEST(Projections, EquirectangularPutsADirectionAtItsLongitudeAndLatitude) {
    const int width = 128, height = 64;
    const CameraParams camera = cameraAtOrigin(CameraProjection::Spherical);
    std::vector<Vec3f> positions;
    std::vector<Vec2f> predicted;
    for (auto [azimuth, elevation] : {std::pair{50.0f, 20.0f}, {-120.0f, -35.0f}, {0.0f, 0.0f}}) {
        positions.push_back(worldDirection(azimuth, elevation) * 10.0f);
        // Longitude runs over the width with the view direction at the centre; latitude over the
        // height from straight up.
        predicted.push_back({(0.5f + azimuth / 360.0f) * width, (0.5f - elevation / 180.0f) * height});
    }
    expectEmittersAt(camera, width, height, positions, predicted, 0.15f, 0.2);
}

TEST(Projections, FisheyeRadiusFollowsTheAngleFromTheViewDirection) {
    const int size = 96;
    for (FisheyeMapping mapping : {FisheyeMapping::Equidistant, FisheyeMapping::Equisolid}) {
        CameraParams camera = cameraAtOrigin(CameraProjection::Fisheye);
        camera.fisheyeMapping = mapping;
        camera.verticalFovDegrees = 200.0f;
        std::vector<Vec3f> positions;
        std::vector<Vec2f> predicted;
        // (angle from the view direction, angle around it counter-clockwise from the right)
        for (auto [theta, phi] : {std::pair{60.0f, 30.0f}, {95.0f, 200.0f}, {20.0f, -90.0f}}) {
            const float t = theta * kDegree, p = phi * kDegree;
            // Camera space (x right, y up, z forward) to world (z backwards).
            positions.push_back(Vec3f{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), -std::cos(t)} *
                                10.0f);
            const float halfFov = 100.0f * kDegree;
            const float r = mapping == FisheyeMapping::Equidistant
                                ? t / halfFov
                                : std::sin(0.5f * t) / std::sin(0.5f * halfFov);
            const float radiusPixels = r * 0.5f * size;
            predicted.push_back(
                {0.5f * size + radiusPixels * std::cos(p), 0.5f * size - radiusPixels * std::sin(p)});
        }
        expectEmittersAt(camera, size, size, positions, predicted, 0.12f, 0.25);
    }
}

TEST(Projections, OrthographicImagesAPointAtItsOffsetWhateverItsDepth) {
    const int width = 96, height = 64;
    CameraParams camera = cameraAtOrigin(CameraProjection::Orthographic);
    camera.orthographicHeight = 4.0f;  // 16 pixels a unit
    // Two emitters at the same offset, 5 and 20 units away, and one elsewhere.
    const std::vector<Vec3f> positions{{1.0f, 0.5f, -5.0f}, {-1.5f, -1.0f, -20.0f}, {1.0f, 0.5f, -20.0f}};
    std::vector<Vec2f> predicted;
    for (const Vec3f& p : positions)
        predicted.push_back({0.5f * width + 16.0f * p.x, 0.5f * height - 16.0f * p.y});
    // Each on a separate render: the two at the same offset would hide each other.
    for (size_t i = 0; i < positions.size(); ++i)
        expectEmittersAt(camera, width, height, {positions[i]}, {predicted[i]}, 0.1f, 0.1);
}

// The inverse: the ray through a raster position points where the formula says, for pixels
// across each image (world space as in cameraAtOrigin: camera space with z negated).
TEST(Projections, RaysLeaveInTheDirectionsTheFormulasGive) {
    auto expectDirection = [](const Camera& camera, Vec2f raster, Vec3f expected, const char* what) {
        const Vec3f d = camera.generateRay(raster, {0.5f, 0.5f}, 0.0f).ray.direction;
        const Vec3f e = normalize(expected);
        EXPECT_NEAR(d.x, e.x, 2e-5f) << what << " at " << raster.x << ", " << raster.y;
        EXPECT_NEAR(d.y, e.y, 2e-5f) << what << " at " << raster.x << ", " << raster.y;
        EXPECT_NEAR(d.z, e.z, 2e-5f) << what << " at " << raster.x << ", " << raster.y;
    };
    const Camera equirectangular(cameraAtOrigin(CameraProjection::Spherical), 128, 64);
    for (Vec2f raster : {Vec2f{10.5f, 7.25f}, Vec2f{64.0f, 32.0f}, Vec2f{100.0f, 50.0f}}) {
        const float azimuth = (raster.x / 128.0f - 0.5f) * 360.0f,
                    elevation = (0.5f - raster.y / 64.0f) * 180.0f;
        expectDirection(equirectangular, raster, worldDirection(azimuth, elevation), "equirectangular");
    }
    for (FisheyeMapping mapping : {FisheyeMapping::Equidistant, FisheyeMapping::Equisolid}) {
        CameraParams params = cameraAtOrigin(CameraProjection::Fisheye);
        params.fisheyeMapping = mapping;
        params.verticalFovDegrees = 200.0f;
        const Camera fisheye(params, 96, 96);
        for (Vec2f raster : {Vec2f{60.0f, 20.0f}, Vec2f{48.0f, 48.0f}, Vec2f{5.0f, 70.0f}}) {
            const float x = (raster.x - 48.0f) / 48.0f, y = (48.0f - raster.y) / 48.0f, r = std::hypot(x, y);
            const float halfFov = 100.0f * kDegree;
            const float theta = mapping == FisheyeMapping::Equidistant
                                    ? r * halfFov
                                    : 2.0f * std::asin(r * std::sin(0.5f * halfFov));
            const float phi = std::atan2(y, x);
            expectDirection(
                fisheye, raster,
                {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta)},
                "fisheye");
        }
    }
    CameraParams params = cameraAtOrigin(CameraProjection::Orthographic);
    params.orthographicHeight = 4.0f;
    const Camera orthographic(params, 96, 64);
    for (Vec2f raster : {Vec2f{10.0f, 5.0f}, Vec2f{80.5f, 60.0f}}) {
        const Ray ray = orthographic.generateRay(raster, {0.5f, 0.5f}, 0.0f).ray;
        EXPECT_NEAR(ray.origin.x, (raster.x - 48.0f) / 16.0f, 1e-5f);
        EXPECT_NEAR(ray.origin.y, (32.0f - raster.y) / 16.0f, 1e-5f);
        EXPECT_NEAR(ray.origin.z, 0.0f, 1e-6f);
        expectDirection(orthographic, raster, {0.0f, 0.0f, -1.0f}, "orthographic");
    }
}

// A spherical image of nothing but an environment, at the environment map's resolution, looking
// along +z with +y up: every pixel sees exactly its own texel.
TEST(Projections, SphericalImageOfAnEnvironmentIsItsMap) {
    for (auto [projectionMapping, environmentMapping] :
         {std::pair{SphericalMapping::Equirectangular, EnvironmentMapping::Equirectangular},
          {SphericalMapping::EqualArea, EnvironmentMapping::EqualArea}}) {
        const int width = projectionMapping == SphericalMapping::EqualArea ? 32 : 64, height = 32;
        EnvironmentImage image{width, height, {}, environmentMapping};
        for (int i = 0; i < width * height; ++i) {
            const uint64_t h = hashWords(7, uint64_t(i));
            image.texels.push_back({bitsToUnitFloat(uint32_t(h)), bitsToUnitFloat(uint32_t(h >> 32)), 0.5f});
        }
        Scene scene;
        scene.film = {width, height, 16, FilterKind::Box, 0.5f};
        scene.camera.lookFrom = {0.0f, 0.0f, 0.0f};
        scene.camera.lookAt = {0.0f, 0.0f, 1.0f};
        scene.camera.projection = CameraProjection::Spherical;
        scene.camera.sphericalMapping = projectionMapping;
        scene.integrator.maxDepth = 0;
        scene.environment = EnvironmentLight::fromImage(image, Rgb(1.0f), Transform());
        for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
            Film film(width, height);
            RenderOptions options;
            options.accelerator = accelerator;
            render(scene, options, film);
            // Samples on a texel's edge may round into the neighbour: allow a few pixels.
            int mismatched = 0;
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x)
                    if (std::abs(film.at(x, y).mean().r - image.at(x, y).r) > 1e-4f) ++mismatched;
            EXPECT_LE(mismatched, width * height / 100) << "mapping " << int(projectionMapping);
        }
    }
}

TEST(Projections, MirroredEquirectangularReversesTheColumns) {
    CameraParams camera = cameraAtOrigin(CameraProjection::Spherical);
    const Camera plain(camera, 64, 32);
    camera.mirrorColumns = true;
    const Camera mirrored(camera, 64, 32);
    for (float x : {3.5f, 20.25f, 47.0f}) {
        const Vec3f a = plain.generateRay({x, 11.0f}, {0.5f, 0.5f}, 0.0f).ray.direction;
        const Vec3f b = mirrored.generateRay({64.0f - x, 11.0f}, {0.5f, 0.5f}, 0.0f).ray.direction;
        EXPECT_NEAR(a.x, b.x, 1e-5f);
        EXPECT_NEAR(a.y, b.y, 1e-5f);
        EXPECT_NEAR(a.z, b.z, 1e-5f);
    }
}

// Beyond 180 degrees from the view direction an equidistant fisheye reaches nothing: those pixels
// are black under a white sky, the others white.
TEST(Projections, FisheyeBeyondItsReachIsBlack) {
    const int size = 64;
    Scene scene;
    scene.film = {size, size, 4, FilterKind::Box, 0.5f};
    scene.camera = cameraAtOrigin(CameraProjection::Fisheye);
    scene.camera.verticalFovDegrees = 300.0f;  // 180 degrees at 0.6 of the disk's radius
    scene.integrator.maxDepth = 0;
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    Film film(size, size);
    render(scene, RenderOptions{}, film);
    int wrong = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double r = std::hypot(x + 0.5 - 0.5 * size, y + 0.5 - 0.5 * size) / (0.5 * size);
            const double theta = r * 150.0;                              // degrees
            if (std::abs(theta - 180.0) < 150.0 / 32.0 * 1.5) continue;  // pixels the edge crosses
            const float expected = theta < 180.0 ? 1.0f : 0.0f;
            if (std::abs(film.at(x, y).mean().g - expected) > 1e-6f) ++wrong;
        }
    EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace penumbra
