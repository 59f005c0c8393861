// Motion blur against exact shutter fractions. A black quad moves in front of a constant white
// background (radiance 1): a pixel's value is 1 minus the fraction of the shutter during which
// the quad covers it. The camera's field of view is tiny, so the pixel footprint is a point.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

TransformKey translation(Vec3f t) {
    TransformKey key;
    key.translation = t;
    return key;
}

TransformKey rotationAboutZ(float degrees) {
    TransformKey key;
    key.rotation = Quaternion::fromAxisAngle({0, 0, 1}, degrees);
    return key;
}

struct PixelEstimate {
    double mean, standardError;
};

RenderOptions optionsFor(AcceleratorKind accelerator) {
    RenderOptions options;
    options.accelerator = accelerator;
    return options;
}

PixelEstimate renderMean(const Scene& scene, AcceleratorKind accelerator) {
    Film film(scene.film.width, scene.film.height);
    render(scene, optionsFor(accelerator), film);
    double sum = 0, sumSquares = 0, count = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            sum += film.at(x, y).radiance[0];
            sumSquares += film.at(x, y).radianceSquared[0];
            count += film.at(x, y).weight;
        }
    const double mean = sum / count;
    return {mean, std::sqrt(std::max(0.0, sumSquares / count - mean * mean) / count)};
}

Scene movingQuadScene(std::vector<TransformKey> keys, bool deform) {
    Scene scene;
    scene.film = {4, 4, 256, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0, 0, 0};
    scene.camera.lookAt = {0, 0, -1};
    scene.camera.verticalFovDegrees = 0.01f;
    scene.camera.shutterOpen = 0.0f;
    scene.camera.shutterClose = 1.0f / 48.0f;
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    // A unit-wide quad: x in [0, 1] before its motion, at depth 2.
    TriangleMesh quad = testing::makeQuad({0, -5, -2}, {1, 0, 0}, {0, 10, 0}, 0);
    if (deform) {
        // The same motion expressed as per-vertex keys.
        for (const TransformKey& key : keys) {
            std::vector<Vec3f> moved = quad.positions;
            for (Vec3f& p : moved) p = p + key.translation;
            quad.positionKeys.push_back(moved);
        }
        quad.positions = quad.positionKeys.front();
    } else {
        quad.motion.keys = std::move(keys);
    }
    scene.meshes.push_back(quad);
    return scene;
}

// Every case runs on both traversal backends, which interpolate motion the same way.
class MotionBlur : public ::testing::TestWithParam<AcceleratorKind> {};

INSTANTIATE_TEST_SUITE_P(Backends, MotionBlur,
                         ::testing::Values(AcceleratorKind::Embree, AcceleratorKind::Bvh),
                         [](const auto& info) {
                             return std::string(info.param == AcceleratorKind::Bvh ? "Bvh" : "Embree");
                         });

TEST_P(MotionBlur, MovingQuadCoversThePixelForTheExactShutterFraction) {
    // The quad's left edge goes from x = -3 to x = +1 over the shutter (through x = -1 at the
    // middle key): it covers x = 0 while the edge is in [-1, 0], i.e. for t in [0.5, 0.75].
    for (bool deform : {false, true}) {
        const Scene scene = movingQuadScene(
            {translation({-3, 0, 0}), translation({-1, 0, 0}), translation({1, 0, 0})}, deform);
        const PixelEstimate e = renderMean(scene, GetParam());
        // Each sample is 0 or 1 (Bernoulli, p = 0.75): the film's i.i.d. standard error bounds the
        // stratified sampler's error.
        EXPECT_NEAR(e.mean, 0.75, 5.0 * e.standardError + 1e-6)
            << (deform ? "per-vertex keys" : "transform keys");
        EXPECT_GT(e.standardError, 0.0);
    }
}

TEST_P(MotionBlur, UnevenSpeedBetweenKeysIsFollowed) {
    // Keys at x = -1, 0, 4: the edge crosses [-1, 0] during the first half exactly.
    const Scene scene =
        movingQuadScene({translation({-1, 0, 0}), translation({0, 0, 0}), translation({4, 0, 0})}, false);
    const PixelEstimate e = renderMean(scene, GetParam());
    EXPECT_NEAR(e.mean, 0.5, 5.0 * e.standardError + 1e-6);
}

// A "clock hand" (a bar from the centre outwards) turning a full circle during the shutter sweeps
// a rotationally symmetric image; half a turn does not.
double rotationalAsymmetry(float totalDegrees, AcceleratorKind accelerator) {
    Scene scene;
    const int size = 32;
    scene.film = {size, size, 64, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0, 0, 0};
    scene.camera.lookAt = {0, 0, -1};
    scene.camera.verticalFovDegrees = 40.0f;
    scene.camera.shutterClose = 1.0f;
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    TriangleMesh hand = testing::makeQuad({0, -0.15f, 0}, {0.6f, 0, 0}, {0, 0.3f, 0}, 0);
    for (int k = 0; k <= 8; ++k) {
        TransformKey key = rotationAboutZ(totalDegrees * k / 8.0f);
        key.translation = {0, 0, -2};
        hand.motion.keys.push_back(key);
    }
    scene.meshes.push_back(hand);
    Film film(size, size);
    render(scene, optionsFor(accelerator), film);
    // Compare each pixel with the one a quarter turn away, normalised by their noise.
    double chiSquare = 0;
    int count = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const int rx = size - 1 - y, ry = x;  // (x, y) turned by 90 degrees about the centre
            const double a = film.at(x, y).mean().r, b = film.at(rx, ry).mean().r;
            const double variance = film.at(x, y).varianceOfMean().r + film.at(rx, ry).varianceOfMean().r;
            if (variance > 0) {
                chiSquare += (a - b) * (a - b) / variance;
                ++count;
            }
        }
    return count ? chiSquare / count : 0.0;
}

TEST_P(MotionBlur, FullTurnLeavesARotationallySymmetricImage) {
    // Per pixel pair, (a - b)^2 / (var a + var b) has mean 1 when the image is symmetric (and
    // below 1 with stratification, whose variance estimate is pessimistic).
    const double fullTurn = rotationalAsymmetry(360.0f, GetParam());
    // With about 1000 pixel pairs the statistic has a standard deviation near 0.05 under symmetry.
    EXPECT_LT(fullTurn, 1.5);
    const double halfTurn = rotationalAsymmetry(180.0f, GetParam());
    EXPECT_GT(halfTurn, 10.0) << "the control (half a turn) should be clearly asymmetric";
}

TEST_P(MotionBlur, CameraMotionBlursLikeObjectMotion) {
    // Moving the camera right by 4 units is the static quad moving left by 4, relative to it.
    Scene scene = movingQuadScene({translation({0, 0, 0}), translation({0, 0, 0})}, false);
    scene.meshes[0].motion.keys.clear();
    // Quad static at x in [0, 1]; camera from x = -1 to x = 3 covers it for t in [0.25, 0.5].
    scene.camera.motion = {CameraPose{{-1, 0, 0}, {-1, 0, -1}, {0, 1, 0}},
                           CameraPose{{3, 0, 0}, {3, 0, -1}, {0, 1, 0}}};
    const PixelEstimate e = renderMean(scene, GetParam());
    EXPECT_NEAR(e.mean, 0.75, 5.0 * e.standardError + 1e-6);
}

}  // namespace
}  // namespace penumbra
