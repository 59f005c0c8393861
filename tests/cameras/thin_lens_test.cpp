// Depth of field against thin-lens optics. A small emitting sphere on the optical axis at depth d,
// with the lens focused at distance F and an aperture of radius A, images to a blur disk of
// radius A |1/F - 1/d| on the image plane at unit distance (pinhole projection of the focus
// plane), i.e. R = A |1/F - 1/d| (H / 2) / tan(fov / 2) pixels.
//
// The radius is measured from the image's second moment: a uniform disk of radius R has
// E[r^2] = R^2 / 2, and convolving it with the sphere's own image (a disk of radius rho) and the
// one-pixel box filter adds rho^2 / 2 and 1/6 px^2, which are subtracted.
#include <gtest/gtest.h>

#include <cmath>

#include "core/hash.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

constexpr int kSize = 96;
constexpr float kFov = 30.0f;
const float kPixelsPerUnit = 0.5f * kSize / std::tan(0.5f * kFov * kPi / 180.0f);

struct Moments {
    double cx = 0, cy = 0;  // centroid, pixels
    double r2 = 0;          // E[r^2] about the centroid
    double total = 0;       // sum of pixel values
};

Scene pointSourceScene(float depth, float sphereRadius, float aperture, float focus, int blades, int spp) {
    Scene scene;
    scene.film = {kSize, kSize, spp, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0, 0, 0};
    scene.camera.lookAt = {0, 0, -1};
    scene.camera.verticalFovDegrees = kFov;
    scene.camera.apertureRadius = aperture;
    scene.camera.focusDistance = focus;
    scene.camera.apertureBlades = blades;
    scene.integrator.maxDepth = 0;
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    Sphere sphere;
    sphere.center = {0.0f, 0.0f, -depth};
    sphere.radius = sphereRadius;
    sphere.emission.radiance = Rgb(1.0f);
    scene.spheres.push_back(sphere);
    return scene;
}

Film renderScene(const Scene& scene) {
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    return film;
}

Moments momentsOf(const Film& film) {
    Moments m;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const double v = film.at(x, y).mean().g;
            m.total += v;
            m.cx += v * (x + 0.5);
            m.cy += v * (y + 0.5);
        }
    m.cx /= m.total;
    m.cy /= m.total;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const double v = film.at(x, y).mean().g, dx = x + 0.5 - m.cx, dy = y + 0.5 - m.cy;
            m.r2 += v * (dx * dx + dy * dy);
        }
    m.r2 /= m.total;
    return m;
}

// Image radius of a sphere of radius r at distance d: tan of its angular radius, in pixels.
double sphereImageRadius(double r, double d) { return r / std::sqrt(d * d - r * r) * kPixelsPerUnit; }

TEST(ThinLens, CircleOfConfusionMatchesThinLensFormula) {
    const float aperture = 0.5f, focus = 2.0f, depth = 4.0f, sphereRadius = 0.05f;
    const Film film = renderScene(pointSourceScene(depth, sphereRadius, aperture, focus, 0, 1024));
    const Moments m = momentsOf(film);
    const double rho = sphereImageRadius(sphereRadius, depth);
    const double measured = std::sqrt(2.0 * (m.r2 - rho * rho / 2.0 - 1.0 / 6.0));
    const double expected = aperture * std::abs(1.0 / focus - 1.0 / depth) * kPixelsPerUnit;
    EXPECT_NEAR(measured / expected, 1.0, 0.03)
        << "measured " << measured << " px, expected " << expected << " px";
    EXPECT_NEAR(m.cx, kSize / 2.0, 0.5);
    EXPECT_NEAR(m.cy, kSize / 2.0, 0.5);
}

TEST(ThinLens, PointInFrontOfTheFocusPlaneBlursByTheSameFormula) {
    const float aperture = 0.2f, focus = 3.0f, depth = 1.5f, sphereRadius = 0.02f;
    const Film film = renderScene(pointSourceScene(depth, sphereRadius, aperture, focus, 0, 1024));
    const Moments m = momentsOf(film);
    const double rho = sphereImageRadius(sphereRadius, depth);
    const double measured = std::sqrt(2.0 * (m.r2 - rho * rho / 2.0 - 1.0 / 6.0));
    const double expected = aperture * std::abs(1.0 / focus - 1.0 / depth) * kPixelsPerUnit;
    EXPECT_NEAR(measured / expected, 1.0, 0.03)
        << "measured " << measured << " px, expected " << expected << " px";
}

TEST(ThinLens, PointOnTheFocusPlaneStaysSharp) {
    const float sphereRadius = 0.005f, depth = 2.0f;
    const Film film = renderScene(pointSourceScene(depth, sphereRadius, 0.5f, depth, 0, 256));
    const Moments m = momentsOf(film);
    // The image centre is a pixel corner, so even a perfect point spreads over four pixel centres
    // at r^2 = 1/2; the sphere's image adds under 0.1 px^2. One pixel of rms radius is sharp (the
    // same point 10% further away, out of focus, measures about 4 px).
    EXPECT_LT(std::sqrt(m.r2), 1.0) << "E[r^2] = " << m.r2;
    const Moments defocused =
        momentsOf(renderScene(pointSourceScene(depth * 1.1f, sphereRadius, 0.5f, depth, 0, 256)));
    EXPECT_GT(std::sqrt(defocused.r2), 2.0) << "E[r^2] = " << defocused.r2;
}

// The n-fold angular moment <r^2 cos(n theta)> / <r^2> of an image: zero for a round blur, and
// for a regular n-gon with a vertex at theta = 0 a fixed positive value, computed below
// independently by Monte Carlo over the polygon.
double angularMoment(const Film& film, const Moments& m, int n) {
    double sum = 0, norm = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const double v = film.at(x, y).mean().g;
            // Raster y points down; flip it so angles are counter-clockwise as on the lens.
            const double dx = x + 0.5 - m.cx, dy = -(y + 0.5 - m.cy);
            const double r2 = dx * dx + dy * dy;
            sum += v * r2 * std::cos(n * std::atan2(dy, dx));
            norm += v * r2;
        }
    return sum / norm;
}

double polygonAngularMoment(int n) {
    // Uniform points in the unit disk, kept when inside the regular n-gon with a vertex at angle 0.
    double sum = 0, norm = 0;
    const double apothem = std::cos(kPi / n);
    for (uint64_t i = 0; i < 2000000; ++i) {
        const uint64_t h = hashWords(12345, i);
        const double x = 2.0 * bitsToUnitFloat(uint32_t(h)) - 1.0,
                     y = 2.0 * bitsToUnitFloat(uint32_t(h >> 32)) - 1.0;
        const double theta = std::atan2(y, x), r2 = x * x + y * y;
        const double sector =
            std::fmod(theta + 2 * kPi, 2 * kPi / n) - kPi / n;  // angle from the edge normal
        if (std::sqrt(r2) * std::cos(sector) > apothem) continue;
        sum += r2 * std::cos(n * theta);
        norm += r2;
    }
    return sum / norm;
}

TEST(ThinLens, BladedApertureImagesToAPolygon) {
    for (int blades : {5, 6}) {
        const Film film = renderScene(pointSourceScene(4.0f, 0.03f, 0.5f, 2.0f, blades, 1024));
        const Moments m = momentsOf(film);
        const double measured = angularMoment(film, m, blades);
        const double expected = polygonAngularMoment(blades);
        // The sphere's image and the pixel filter round the corners a little (about 10% of the
        // radius for the sphere), so 25% is allowed; a round aperture gives 0.
        EXPECT_NEAR(measured, expected, 0.25 * expected) << blades << " blades";
        EXPECT_GT(expected, 0.02);
    }
    const Film round = renderScene(pointSourceScene(4.0f, 0.03f, 0.5f, 2.0f, 0, 1024));
    const Moments m = momentsOf(round);
    EXPECT_NEAR(angularMoment(round, m, 6), 0.0, 0.2 * polygonAngularMoment(6));
}

}  // namespace
}  // namespace penumbra
