// The lens-system camera against the lens designs' published optics: the four lens files of
// scenes/lenses/ read; their focal lengths and back focal distances, traced, against the
// paraxial values of scenes/lenses/README.md (an independent matrix trace) and the designs'
// nominal focal lengths; a point at the focus distance imaged to a spot smaller than a pixel
// (traced, and rendered on both backends); bad lens files refused at their line.
#include <gtest/gtest.h>

#include <cmath>

#include "cameras/aperture.h"
#include "cameras/camera.h"
#include "cameras/lens_file.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/aperture_correlation.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

std::vector<LensSurface> lensFile(const char* name) {
    return readLensFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/lenses/" + name);
}

CameraParams lensCamera(const char* file, float apertureDiameterMm, float focusMetres) {
    CameraParams camera;
    camera.lookFrom = {0.0f, 0.0f, 0.0f};
    camera.lookAt = {0.0f, 0.0f, -1.0f};
    camera.projection = CameraProjection::LensSystem;
    camera.lensSystem.surfaces = lensFile(file);
    camera.lensSystem.apertureDiameterMm = apertureDiameterMm;
    camera.focusDistance = focusMetres;
    return camera;
}

struct Design {
    const char* file;
    size_t surfaces;
    double nominalMm, paraxialFocalMm, paraxialBackFocalMm;
};
// scenes/lenses/README.md.
constexpr Design kDesigns[] = {
    {"dgauss.50mm.dat", 11, 50.0, 50.36, 36.11},
    {"wide.22mm.dat", 13, 22.0, 22.02, 14.32},
    {"telephoto.250mm.dat", 7, 250.0, 249.57, 105.07},
    {"fisheye.10mm.dat", 12, 10.0, 9.99, 23.16},
};

TEST(LensSystem, FocalLengthsAndBackFocalDistancesMatchTheDesigns) {
    for (const Design& d : kDesigns) {
        const CameraParams camera = lensCamera(d.file, 0.0f, 10.0f);
        ASSERT_EQ(camera.lensSystem.surfaces.size(), d.surfaces) << d.file;
        const LensSystemProjection lens(camera, 10.0f, 64, 64);
        const auto c = lens.cardinalPoints();
        const double focalMm = c.focalLength() * 1000.0;
        const double backFocalMm = (lens.rearZ() - c.rearFocalZ) * 1000.0;
        // The trace is at 0.035 mm from the axis, paraxial to 1e-6; float rounding of the
        // positions (metres, ~1e-7 relative) leaves 0.1%.
        EXPECT_NEAR(focalMm, d.paraxialFocalMm, 1e-3 * d.paraxialFocalMm) << d.file;
        EXPECT_NEAR(backFocalMm, d.paraxialBackFocalMm, 1e-3 * d.paraxialFocalMm) << d.file;
        EXPECT_NEAR(focalMm, d.nominalMm, 0.01 * d.nominalMm) << d.file;
        // Front and rear focal lengths are equal with air on both sides.
        EXPECT_NEAR(c.frontFocalZ - c.frontPrincipalZ, c.focalLength(), 1e-3 * c.focalLength()) << d.file;
    }
}

// Rays from the axial point `distance` from the film towards 20000 points spread over the front
// element, traced to the film plane: how many pass, and the rms radius of where they land.
struct Spot {
    int passed = 0;
    double rmsRadius = 0;
};
Spot traceAxialPoint(const LensSystemProjection& lens, float frontRadius, float distance) {
    double sum2 = 0;
    Spot spot;
    for (int i = 0; i < 20000; ++i) {
        const uint64_t h = hashWords(3, uint64_t(i));
        const Vec2f disk =
            sampleUniformDiskConcentric({bitsToUnitFloat(uint32_t(h)), bitsToUnitFloat(uint32_t(h >> 32))});
        const Vec3f origin{0.0f, 0.0f, distance};
        const Vec3f target{disk.x * frontRadius, disk.y * frontRadius, lens.frontZ()};
        const auto out = lens.traceFromScene(origin, target - origin);
        if (!out) continue;
        const float t = -out->origin.z / out->direction.z;
        const Vec3f onFilm = out->origin + out->direction * t;
        sum2 += onFilm.x * onFilm.x + onFilm.y * onFilm.y;
        ++spot.passed;
    }
    spot.rmsRadius = spot.passed > 0 ? std::sqrt(sum2 / spot.passed) : 0.0;
    return spot;
}

// Rays from an axial point 2 m from the film, spread over the front element, traced to the film
// plane: their spot (rms radius) is smaller than a pixel of a 512-pixel-wide 35 mm film, at
// f/5.6; 10% further away the spot is several times larger.
TEST(LensSystem, AnAxialPointAtTheFocusDistanceImagesToASpot) {
    const CameraParams camera = lensCamera("dgauss.50mm.dat", 9.0f, 2.0f);
    const LensSystemProjection lens(camera, 2.0f, 512, 512);
    const float pixel = 2.0f * lens.filmHalfDiagonal() / std::sqrt(2.0f) / 512.0f;
    const float front = 0.5f * camera.lensSystem.surfaces.front().apertureDiameter / 1000.0f;
    auto spotRadius = [&](float distance) {
        const Spot spot = traceAxialPoint(lens, front, distance);
        EXPECT_GT(spot.passed, 1000);
        return spot.rmsRadius;
    };
    const double focused = spotRadius(2.0f), defocused = spotRadius(2.2f);
    EXPECT_LT(focused, 0.5 * pixel) << "pixel " << pixel * 1000 << " mm";
    EXPECT_GT(defocused, 3.0 * focused);
}

// The same through the renderer: a small emitter on the axis at the focus distance images to a
// spot of under a pixel rms at the image centre, on both backends.
TEST(LensSystem, RenderedPointAtTheFocusDistanceIsSharpOnBothBackends) {
    const int size = 96;
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        Scene scene;
        scene.film = {size, size, 256, FilterKind::Box, 0.5f};
        scene.camera = lensCamera("dgauss.50mm.dat", 9.0f, 3.0f);
        scene.integrator.maxDepth = 0;
        scene.materials = {testing::makeLambert(Rgb(0.0f))};
        Sphere sphere;
        sphere.center = {0.0f, 0.0f, -3.0f};
        sphere.radius = 0.002f;  // 0.03 mm on the film: a tenth of a pixel
        sphere.emission.radiance = Rgb(1.0f);
        scene.spheres.push_back(sphere);
        Film film(size, size);
        RenderOptions options;
        options.accelerator = accelerator;
        render(scene, options, film);
        double total = 0, cx = 0, cy = 0, r2 = 0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const double v = film.at(x, y).mean().g;
                total += v, cx += v * (x + 0.5), cy += v * (y + 0.5);
            }
        ASSERT_GT(total, 0.0);
        cx /= total, cy /= total;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const double v = film.at(x, y).mean().g;
                r2 += v * ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy));
            }
        // The centre is a pixel corner: a point spreads over four pixels at r^2 = 1/2.
        EXPECT_LT(std::sqrt(r2 / total), 1.0);
        EXPECT_NEAR(cx, 0.5 * size, 0.25);
        EXPECT_NEAR(cy, 0.5 * size, 0.25);
    }
}

// The entrance pupil's radius: the greatest height at which a ray parallel to the axis passes
// the lens (bisection to 1e-6 of the front element's radius).
float entrancePupilRadius(const LensSystemProjection& lens, float frontRadius) {
    float lo = 0.0f, hi = frontRadius;
    for (int i = 0; i < 24; ++i) {
        const float h = 0.5f * (lo + hi);
        (lens.traceFromScene({h, 0.0f, lens.frontZ() + 0.01f}, {0.0f, 0.0f, -1.0f}) ? lo : hi) = h;
    }
    return lo;
}

// The blur of an axial point off the focus distance, traced, against the thick-lens prediction:
// a point at s from the front principal plane, the lens focused at S, images to a disk of radius
// r = a f / (S - f) |s - S| / s on the film, a the entrance pupil's radius. At f/11 the lens's
// own aberrations (its spot in focus) are under 2% of the blurs measured; the disk's edge is
// measured as sqrt(2) times its rms radius.
TEST(LensSystem, DefocusBlurFollowsTheThickLensPrediction) {
    const float focus = 2.0f;
    const CameraParams camera = lensCamera("dgauss.50mm.dat", 4.5f, focus);
    const LensSystemProjection lens(camera, focus, 512, 512);
    const auto c = lens.cardinalPoints();
    const float f = c.focalLength();
    const float frontRadius = 0.5f * camera.lensSystem.surfaces.front().apertureDiameter / 1000.0f;
    const float a = entrancePupilRadius(lens, frontRadius);
    for (float distance : {1.0f, 1.5f, 3.0f, 6.0f}) {
        const double s = distance - c.frontPrincipalZ, S = focus - c.frontPrincipalZ;
        const double predicted = a * f / (S - f) * std::abs(s - S) / s;
        const Spot spot = traceAxialPoint(lens, frontRadius, distance);
        ASSERT_GT(spot.passed, 100) << distance;
        const double measured = std::sqrt(2.0) * spot.rmsRadius;
        EXPECT_NEAR(measured / predicted, 1.0, 0.05)
            << "at " << distance << " m: " << measured * 1e3 << " mm against " << predicted * 1e3 << " mm";
    }
}

// The shape of the bundle of rays that reach a film point (the bokeh of a far out-of-focus point
// imaged there): round at the centre, and at 80% of the half diagonal, with the stop wide open,
// cut by the front and rear elements' rims into a cat's eye, narrower radially than tangentially.
// Measured as the ratio of the passing rays' rms spread on the rear plane radially (x) and
// tangentially (y).
TEST(LensSystem, OffAxisBokehIsACatsEyeWideOpen) {
    auto axisRatio = [](float apertureMm, float filmFraction) {
        const CameraParams camera = lensCamera("dgauss.50mm.dat", apertureMm, 10.0f);
        const LensSystemProjection lens(camera, 10.0f, 512, 512);
        const float rear = 0.5f * camera.lensSystem.surfaces.back().apertureDiameter / 1000.0f * 1.5f;
        const Vec3f film{filmFraction * lens.filmHalfDiagonal(), 0.0f, 0.0f};
        double sx = 0, sy = 0, sxx = 0, syy = 0;
        int passed = 0;
        for (int i = 0; i < 200000; ++i) {
            const uint64_t h = hashWords(11, uint64_t(i));
            const Vec3f onRear{rear * (2.0f * bitsToUnitFloat(uint32_t(h)) - 1.0f),
                               rear * (2.0f * bitsToUnitFloat(uint32_t(h >> 32)) - 1.0f), lens.rearZ()};
            if (!lens.traceFromFilm(film, onRear - film)) continue;
            sx += onRear.x, sy += onRear.y, sxx += onRear.x * onRear.x, syy += onRear.y * onRear.y;
            ++passed;
        }
        EXPECT_GT(passed, 1000);
        const double vx = sxx / passed - (sx / passed) * (sx / passed),
                     vy = syy / passed - (sy / passed) * (sy / passed);
        return std::sqrt(vx / vy);
    };
    const double centre = axisRatio(0.0f, 0.0f), corner = axisRatio(0.0f, 0.8f);
    EXPECT_NEAR(centre, 1.0, 0.02);
    EXPECT_LT(corner, 0.8) << "centre " << centre;
    // Stopped down to f/8 the stop alone limits the bundle off axis too: round again.
    EXPECT_NEAR(axisRatio(6.0f, 0.8f), 1.0, 0.05);
}

// A white furnace through the lens: under a uniform sky of radiance 1 the film measures the
// irradiance pi sin^2(alpha), alpha the half-angle of the cone of light at the film; for an
// object at infinity and an aplanatic lens sin(alpha) = 1 / (2N), N = f / (2a) (a the entrance
// pupil's radius), so the image's centre is pi / (4 N^2). Away from the centre the image falls
// off, monotonically, and at the stop of f/11 within 5% of the cos^4 law of a thin lens of the
// same focal length (cos^4 of the field angle atan(r / f)): the exit pupil of this design sits
// where a thin lens's would, and no rim cuts the bundles.
TEST(LensSystem, WhiteFurnaceGivesTheIrradianceOfTheLens) {
    const int width = 96, height = 64;
    Scene scene;
    scene.film = {width, height, 256, FilterKind::Box, 0.5f};
    scene.camera = lensCamera("dgauss.50mm.dat", 4.5f, 1000.0f);
    scene.integrator.maxDepth = 0;
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    Film film(width, height);
    render(scene, RenderOptions{}, film);
    const LensSystemProjection lens(scene.camera, 1000.0f, width, height);
    const float f = lens.cardinalPoints().focalLength();
    const float frontRadius = 0.5f * scene.camera.lensSystem.surfaces.front().apertureDiameter / 1000.0f;
    const double n = f / (2.0 * entrancePupilRadius(lens, frontRadius));
    double centre = 0;
    for (int y = height / 2 - 1; y <= height / 2; ++y)
        for (int x = width / 2 - 1; x <= width / 2; ++x) centre += film.at(x, y).mean().g / 4.0;
    EXPECT_NEAR(centre, kPi / (4.0 * n * n), 0.02 * kPi / (4.0 * n * n)) << "N = " << n;
    // Along the middle rows (the film's half width is 0.83 of its half diagonal), in bins of 6 x 4
    // pixels (the noise of a bin is about 0.5%, of a pixel 2%).
    const float filmHalfWidth = lens.filmHalfDiagonal() * width / std::hypot(float(width), float(height));
    double previous = centre * 1.01;
    for (int x0 = width / 2; x0 < width; x0 += 6) {
        double value = 0;
        for (int y = height / 2 - 2; y < height / 2 + 2; ++y)
            for (int x = x0; x < x0 + 6; ++x) value += film.at(x, y).mean().g / 24.0;
        const double r = (x0 + 3 - 0.5 * width) / (0.5 * width) * filmHalfWidth;
        const double cos4 = std::pow(std::cos(std::atan(r / f)), 4.0);
        EXPECT_LT(value, previous * 1.01) << "x " << x0;
        EXPECT_NEAR(value / centre, cos4, 0.05) << "x " << x0 << ", r " << r * 1e3 << " mm";
        previous = value;
    }
}

// The stop shaped by the star image: a point far behind the focus distance, near the axis,
// blurs into the star, upright (the exit pupil is an upright image of the stop, and the cone of
// light crosses over before the film, which the raster turns back). The blur's size comes from
// its second moment against the image's; the film, sampled on the image's grid, correlates with
// the star above 0.8 (the lens's aberrations soften the points more than the thin lens's do) and
// at least 0.1 less with its mirror image.
TEST(LensSystem, OutOfFocusPointImagesToTheStopsApertureImage) {
    constexpr int kSize = 128;
    Scene scene;
    scene.film = {kSize, kSize, 1024, FilterKind::Box, 0.5f};
    scene.camera = lensCamera("dgauss.50mm.dat", 12.0f, 0.6f);
    scene.camera.apertureImage = *builtinApertureImage("star");
    scene.camera.lensSystem.filmDiagonalMm = 10.0f;  // a small film: the field stays near the axis
    scene.integrator.maxDepth = 0;
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    Sphere sphere;
    sphere.center = {0.0f, 0.0f, -20.0f};
    sphere.radius = 0.05f;
    sphere.emission.radiance = Rgb(1.0f);
    scene.spheres.push_back(sphere);
    Film film(kSize, kSize);
    render(scene, RenderOptions{}, film);

    double total = 0, cx = 0, cy = 0, r2 = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double v = film.at(x, y).mean().g;
            total += v, cx += v * (x + 0.5), cy += v * (y + 0.5);
        }
    ASSERT_GT(total, 0.0);
    cx /= total, cy /= total;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            r2 +=
                film.at(x, y).mean().g * ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy));
    r2 /= total;
    const Aperture star = Aperture::image(scene.camera.apertureImage);
    // The star's own second moment over [-1, 1]^2 (about its centre, the origin).
    double imageTotal = 0, imageR2 = 0;
    for (int j = 0; j < 256; ++j)
        for (int i = 0; i < 256; ++i) {
            const float u = -1.0f + 2.0f * (i + 0.5f) / 256, v = 1.0f - 2.0f * (j + 0.5f) / 256;
            const double t = star.transmission({u, v});
            imageTotal += t, imageR2 += t * (u * u + v * v);
        }
    const double scale = std::sqrt(r2 / (imageR2 / imageTotal));  // pixels per unit of the image
    ASSERT_GT(scale, 15.0);
    ASSERT_LT(scale, 0.45 * kSize);
    const double upright = testing::apertureCorrelation(film, star, cx, cy, scale, false);
    const double mirrored = testing::apertureCorrelation(film, star, cx, cy, scale, true);
    EXPECT_GT(upright, 0.8) << "mirrored " << mirrored << ", scale " << scale;
    EXPECT_LT(mirrored, upright - 0.1);
}

TEST(LensSystem, ALensThatCannotFocusSoCloseIsRefused) {
    const CameraParams camera = lensCamera("telephoto.250mm.dat", 0.0f, 0.5f);
    EXPECT_THROW(LensSystemProjection(camera, 0.5f, 64, 64), InputError);
}

TEST(LensFile, BadFilesAreRefusedAtTheirLine) {
    auto messageOf = [](const std::string& text) {
        try {
            parseLensFile(text, "lens.dat");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(messageOf("# a lens\n10 2 1.5 20\n-10 3 1\n").find("lens.dat:3"), std::string::npos);
    EXPECT_NE(messageOf("# a lens\n10 2 1.5 20\n-10 3 1 abc\n").find("\"abc\""), std::string::npos);
    EXPECT_NE(messageOf("10 -2 1.5 20\n").find("thickness"), std::string::npos);
    EXPECT_NE(messageOf("10 2 1.5 0\n").find("diameter"), std::string::npos);
    EXPECT_NE(messageOf("# nothing\n").find("no lens surface"), std::string::npos);
    EXPECT_NE(messageOf("10 2 nan 20\n").find("expected a number"), std::string::npos);
    std::string many;
    for (size_t i = 0; i <= kMaxLensSurfaces; ++i) many += "10 1 1.5 5\n";
    EXPECT_NE(messageOf(many).find("more than"), std::string::npos);
    // Comments anywhere, numbers across lines.
    const auto surfaces = parseLensFile("10 2#c\n1.5 20 # d\n0 1 0 8\n", "lens.dat");
    ASSERT_EQ(surfaces.size(), 2u);
    EXPECT_EQ(surfaces[0].eta, 1.5f);
    EXPECT_EQ(surfaces[1].curvatureRadius, 0.0f);
}

}  // namespace
}  // namespace penumbra
