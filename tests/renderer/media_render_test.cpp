// Participating media through the renderer (renderer/volumetric_path_integrator.h), against closed
// forms: Beer-Lambert transmittance of a slab, a white furnace, single scattering of a point light
// in an infinite medium, delta and ratio tracking through a grid whose optical depth is known, and
// the radiance of emitting grids (a blackbody temperature, an RGB lattice).
//
// Tolerances. Each test renders many pixels that all estimate the same value (a narrow field of
// view, or a value that is the same everywhere), independently of one another; their mean is
// checked against the exact value within 5 standard errors, the standard error estimated from the
// pixels' own spread (with hundreds of pixels the estimate is within a few percent of the true
// one). A correct integrator fails such a check with probability below 1e-6; the seeds are fixed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/colorimetry.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/pixel_mean.h"
#include "tests/support/scene_builders.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::withinSigmas;
using testing::PixelMean;
using testing::renderedChannelMean;

// Simpson's rule for f over [a, b] in `steps` (even) steps.
template <typename F>
double simpson(F&& f, double a, double b, int steps) {
    const double h = (b - a) / steps;
    double sum = f(a) + f(b);
    for (int i = 1; i < steps; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
    return sum * h / 3;
}

// The Henyey-Greenstein phase function of mean cosine g, cosTheta the cosine between wo and wi,
// both pointing away from the scattering point (pbrt-v4's convention, whence + 2 g cosTheta).
double henyeyGreenstein(double g, double cosTheta) {
    return (1 - g * g) / (4 * M_PI * std::pow(1 + g * g + 2 * g * cosTheta, 1.5));
}

// A camera at `from` looking at `to` with a field of view so narrow that every pixel sees the
// same ray (to within 1e-4 radians).
void lookNarrowly(Scene& scene, Vec3f from, Vec3f to, Vec3f up = {0.0f, 1.0f, 0.0f}) {
    scene.camera.lookFrom = from;
    scene.camera.lookAt = to;
    scene.camera.up = up;
    scene.camera.verticalFovDegrees = 0.005f;
}

uint32_t addInterfaceMaterial(Scene& scene) {
    scene.materials.push_back(Material(Interface{}));
    return uint32_t(scene.materials.size() - 1);
}

// A slab of pure absorber between z = -d/2 and z = d/2, bounded by two interface quads, in front
// of a uniform background of radiance 1: every camera ray through it carries exp(-sigma_a d),
// channel by channel (chromatic: distances are sampled with one channel's coefficient and the
// channels weighted by spectral MIS).
TEST(Media, HomogeneousSlabTransmitsBeerLambert) {
    const float thickness = 1.0f;
    const Rgb sigmaA(0.5f, 1.0f, 2.0f);
    Scene scene;
    scene.film = {16, 16, 1024, FilterKind::Box, 0.5f};
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    scene.media.push_back(HomogeneousMedium{sigmaA, Rgb(0.0f), Rgb(0.0f), {}});
    scene.mediumNames = {"absorber"};
    const uint32_t boundary = addInterfaceMaterial(scene);
    TriangleMesh front = testing::makeQuad({-2, -2, thickness / 2}, {4, 0, 0}, {0, 4, 0}, boundary);
    TriangleMesh back = testing::makeQuad({-2, -2, -thickness / 2}, {0, 4, 0}, {4, 0, 0}, boundary);
    front.media.inside = back.media.inside = 0;  // the normals point out of the slab
    scene.meshes = {front, back};
    lookNarrowly(scene, {0.1f, 0.2f, 5.0f}, {0.1f, 0.2f, 0.0f});
    for (int c = 0; c < 3; ++c) {
        const PixelMean m = renderedChannelMean(scene, c);
        EXPECT_TRUE(withinSigmas(m.mean, std::exp(-double(sigmaA[c]) * thickness), m.standardError))
            << "channel " << c;
    }
}

// A white furnace: a sphere of non-absorbing medium (albedo 1, chromatic, anisotropic) in a
// uniform environment of radiance 1. Light is neither created nor lost, so every pixel sees 1,
// whatever the paths do inside: next-event estimation at medium vertices, phase sampling, MIS
// between them, spectral MIS and Russian roulette all have to be right for the mean to be 1.
TEST(Media, NonAbsorbingSphereInAUniformEnvironmentIsAWhiteFurnace) {
    Scene scene;
    scene.film = {24, 24, 256, FilterKind::Box, 0.5f};
    scene.integrator.maxDepth = 1000;
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    scene.media.push_back(HomogeneousMedium{Rgb(0.0f), Rgb(1.0f, 2.0f, 3.0f), Rgb(0.0f), {0.6f}});
    scene.mediumNames = {"cloud"};
    Sphere sphere;
    sphere.center = {0, 0, 0};
    sphere.radius = 1.0f;
    sphere.material = addInterfaceMaterial(scene);
    sphere.media.inside = 0;
    scene.spheres = {sphere};
    scene.camera.lookFrom = {0, 0, 4};
    scene.camera.lookAt = {0, 0, 0};
    scene.camera.verticalFovDegrees = 25.0f;  // the sphere fills the middle of the image
    for (int c = 0; c < 3; ++c) {
        const PixelMean m = renderedChannelMean(scene, c);
        EXPECT_TRUE(withinSigmas(m.mean, 1.0, m.standardError)) << "channel " << c;
    }
}

// Single scattering of a point light of intensity I at `light`, seen by a camera ray x(t) = o + t w
// inside an infinite homogeneous medium (max_depth 1: one scattering event):
//   L = integral over t of sigma_s e^{-sigma_t t} p(-w, l(t)) I e^{-sigma_t r(t)} / r(t)^2 dt,
// r(t) = |light - x(t)| and l(t) the unit direction to the light, HG phase function. Integrated
// here by Simpson's rule over [0, 80] (e^{-sigma_t 80} < 1e-17) in 2^18 steps, with the light
// 1 unit off the ray, where the integrand's peak is 1 unit wide: far more precise than the test.
double singleScatteringIntegral(double sigmaS, double sigmaT, double g, double intensity, Vec3f light) {
    auto integrand = [&](double t) {
        const double dx = light.x, dy = light.y, dz = light.z - t;  // the ray runs along +z from 0
        const double r2 = dx * dx + dy * dy + dz * dz, r = std::sqrt(r2);
        const double cosTheta = -dz / r;  // between wo = -z and the direction to the light
        return sigmaS * std::exp(-sigmaT * t) * henyeyGreenstein(g, cosTheta) * intensity *
               std::exp(-sigmaT * r) / r2;
    };
    return simpson(integrand, 0.0, 80.0, 1 << 18);
}

// A camera at the origin looking along +z from inside an infinite homogeneous medium, one
// scattering event (max_depth 1): the single-scattering tests' scene, lights to be added.
Scene singleScatteringScene(Rgb sigmaA, Rgb sigmaS, float g) {
    Scene scene;
    scene.film = {16, 16, 1024, FilterKind::Box, 0.5f};
    scene.integrator.maxDepth = 1;
    scene.media.push_back(HomogeneousMedium{sigmaA, sigmaS, Rgb(0.0f), {g}});
    scene.mediumNames = {"fog"};
    scene.cameraMedium = 0;
    lookNarrowly(scene, {0, 0, 0}, {0, 0, 1});
    return scene;
}

TEST(Media, SingleScatteringOfAPointLightMatchesItsIntegral) {
    const Rgb sigmaA(0.1f, 0.05f, 0.2f), sigmaS(0.2f, 0.4f, 0.3f);
    const float g = 0.4f, intensity = 10.0f;
    const Vec3f light{1.0f, 0.0f, 2.0f};
    Scene scene = singleScatteringScene(sigmaA, sigmaS, g);
    scene.lights.push_back(PointLight{light, Rgb(intensity)});
    for (int c = 0; c < 3; ++c) {
        const double exact = singleScatteringIntegral(sigmaS[c], sigmaA[c] + sigmaS[c], g, intensity, light);
        const PixelMean m = renderedChannelMean(scene, c);
        EXPECT_TRUE(withinSigmas(m.mean, exact, m.standardError)) << "channel " << c;
    }
}

// A grid whose density rises linearly along x over [0, 1]^3 (nx = 8 lattice values at the cells'
// centres, the same along y and z): along the line y = z = 1/2 the density is piecewise linear,
// blending to half the outermost values at the faces (the lattice's convention), so its optical
// depth is a sum of trapezoids, written out here. Pure absorption, so the transmittance
// exp(-depth) is what both trackers estimate.
GridMedium linearRampGrid(float densityScale) {
    GridMedium grid;
    grid.sigmaA = Rgb(densityScale);
    grid.sigmaS = Rgb(0.0f);
    grid.density.nx = 8;
    grid.density.ny = grid.density.nz = 2;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 8; ++x) grid.density.values.push_back((float(x) + 0.5f) / 8.0f);
    grid.buildMajorants();
    return grid;
}

double linearRampOpticalDepth(double densityScale) {
    const int n = 8;
    auto v = [&](int i) { return (i + 0.5) / n; };
    // The half cells at the faces, from half the outermost value to it, then the cells between centres.
    double depth = (0.5 / n) * (0.5 * v(0) + v(0)) / 2 + (0.5 / n) * (v(n - 1) + 0.5 * v(n - 1)) / 2;
    for (int i = 0; i + 1 < n; ++i) depth += (1.0 / n) * (v(i) + v(i + 1)) / 2;
    return densityScale * depth;
}

// Single scattering of a small quad light (one-sided, radiance Le, facing the ray's line) seen by a
// camera ray along +z in an infinite homogeneous medium (max_depth 1):
//   L = integral over t of sigma_s e^{-sigma_t t} integral over the quad of
//       p(-w, l) Le cos_y e^{-sigma_t r} / r^2 dA dt,
// here by Simpson's rule in t (2^12 steps over [0, 60]) and the midpoint rule on a 48 x 48 grid of
// the quad, whose integrand varies smoothly over it (the quad is 0.5 wide at a distance of 1 from
// the ray): both far more precise than the test. Three strategies estimate it together: distance
// sampling and equiangular sampling of the scattering point, each with light sampling, and phase
// sampling that hits the light; the balance heuristic weighs all three, so a weight that does not
// sum to one shows here.
double singleScatteringOfAQuadLight(double sigmaS, double sigmaT, double g, double le, Vec3f corner,
                                    Vec3f edge1, Vec3f edge2) {
    const Vec3f normal = normalize(cross(edge1, edge2));
    const double area = length(cross(edge1, edge2));
    const int n = 48;
    auto atDistance = [&](double t) {
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const Vec3f y = corner + edge1 * ((i + 0.5f) / n) + edge2 * ((j + 0.5f) / n);
                const double dx = y.x, dy = y.y, dz = y.z - t;
                const double r2 = dx * dx + dy * dy + dz * dz, r = std::sqrt(r2);
                const double cosY = -(normal.x * dx + normal.y * dy + normal.z * dz) / r;
                if (cosY <= 0.0) continue;
                sum += henyeyGreenstein(g, -dz / r) * le * cosY * std::exp(-sigmaT * r) / r2;
            }
        return sigmaS * std::exp(-sigmaT * t) * sum * area / (n * n);
    };
    return simpson(atDistance, 0.0, 60.0, 1 << 12);
}

TEST(Media, SingleScatteringOfAQuadLightMatchesItsIntegral) {
    const Rgb sigmaA(0.05f, 0.1f, 0.02f), sigmaS(0.3f, 0.2f, 0.4f);
    const float g = 0.3f, le = 20.0f;
    const Vec3f corner{1.0f, -0.25f, 1.75f}, edge1{0.0f, 0.0f, 0.5f}, edge2{0.0f, 0.5f, 0.0f};  // faces -x
    Scene scene = singleScatteringScene(sigmaA, sigmaS, g);
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    TriangleMesh light = testing::makeQuad(corner, edge1, edge2, 0);
    light.emission.radiance = Rgb(le);
    scene.meshes.push_back(light);
    for (int c = 0; c < 3; ++c) {
        const double exact =
            singleScatteringOfAQuadLight(sigmaS[c], sigmaA[c] + sigmaS[c], g, le, corner, edge1, edge2);
        const PixelMean m = renderedChannelMean(scene, c);
        EXPECT_TRUE(withinSigmas(m.mean, exact, m.standardError))
            << "channel " << c << ": " << m.mean << " +- " << m.standardError << " vs " << exact;
    }
}

// Delta tracking: camera rays along x through the grid (the camera sits in the grid's medium,
// which is empty outside the grid's box) against a background of radiance 1.
TEST(Media, DeltaTrackingThroughAGridMatchesItsOpticalDepth) {
    const float scale = 1.5f;
    Scene scene;
    scene.film = {16, 16, 1024, FilterKind::Box, 0.5f};
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    scene.media.push_back(linearRampGrid(scale));
    scene.mediumNames = {"ramp"};
    scene.cameraMedium = 0;
    lookNarrowly(scene, {-1.0f, 0.5f, 0.5f}, {2.0f, 0.5f, 0.5f});
    const PixelMean m = renderedChannelMean(scene, 0);
    EXPECT_TRUE(withinSigmas(m.mean, std::exp(-linearRampOpticalDepth(scale)), m.standardError));
}

// Ratio tracking: a Lambert plane at x = 2 facing the grid, lit through it along +x by a
// directional light of irradiance E; the camera looks at the plane from beside the grid, so that
// only the shadow rays cross it: L = albedo / pi * E * exp(-depth), on both backends.
TEST(Media, RatioTrackingOfShadowRaysThroughAGridMatchesItsOpticalDepth) {
    const float scale = 1.5f, albedo = 0.8f, irradiance = 3.0f;
    Scene scene;
    scene.film = {16, 16, 1024, FilterKind::Box, 0.5f};
    scene.integrator.maxDepth = 1;
    scene.media.push_back(linearRampGrid(scale));
    scene.mediumNames = {"ramp"};
    scene.cameraMedium = 0;
    scene.materials = {testing::makeLambert(Rgb(albedo))};
    scene.meshes.push_back(testing::makeQuad({2, -5, -5}, {0, 0, 10}, {0, 10, 0}, 0));  // normal -x
    scene.lights.push_back(DirectionalLight{{1.0f, 0.0f, 0.0f}, Rgb(irradiance)});
    lookNarrowly(scene, {1.5f, 0.5f, 2.0f}, {2.0f, 0.5f, 0.5f});
    const double exact = albedo / kPi * irradiance * std::exp(-linearRampOpticalDepth(scale));
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        const PixelMean m = renderedChannelMean(scene, 0, accelerator);
        EXPECT_TRUE(withinSigmas(m.mean, exact, m.standardError));
    }
}

// A hostile grid: one voxel of density 1e30 in a corner, everything else empty. Its coarse
// majorant cell (2 voxels a side) is 1e30 too, so a ray through that cell but out of the voxel's
// reach (trilinear: within one voxel of its centre; here along z at x = y = 1.75 voxels, where the
// density is exactly 0) meets only null collisions, some 1e28 of them. The tracking gives up after
// kMaxCollisionsPerRay: the render ends, and the ray counts as blocked (black), not as crossing
// empty space (1).
// With a density of 1e3 instead, the same ray makes a few hundred null collisions, each of weight
// exactly 1, and sees the background.
TEST(Media, AHostileMajorantEndsTheRayInsteadOfTrackingForEver) {
    auto pixel = [](float cornerDensity) {
        GridMedium grid;
        grid.sigmaA = Rgb(1.0f);
        grid.sigmaS = Rgb(0.0f);
        grid.density.nx = grid.density.ny = grid.density.nz = 32;
        grid.density.values.assign(32 * 32 * 32, 0.0f);
        grid.density.values[0] = cornerDensity;
        grid.buildMajorants();
        Scene scene;
        scene.film = {1, 1, 1, FilterKind::Box, 0.5f};
        scene.environment = EnvironmentLight::constant(Rgb(1.0f));
        scene.media.push_back(grid);
        scene.mediumNames = {"corner"};
        scene.cameraMedium = 0;
        const float side = 1.75f / 32.0f;
        lookNarrowly(scene, {side, side, -1.0f}, {side, side, 2.0f});
        return renderedChannelMean(scene, 0).mean;
    };
    EXPECT_EQ(pixel(1e3f), 1.0);
    EXPECT_EQ(pixel(1e30f), 0.0);
}

// Emission. A camera inside a grid medium over the unit cube looks along +x at a black wall at
// x = 0.9, from x = 0.1: the ray stays where every lattice value it blends is a cell's own (the
// outermost centres are at 1/16 and 15/16 along x, 1/6 and 5/6 across), so the medium is uniform
// along it and, purely absorbing with sigma_a, it sees Le * (1 - exp(-sigma_a * 0.8)).
constexpr float kEmissionPath = 0.8f;

void lookAlongXAtABlackWall(Scene& scene) {
    scene.film = {16, 16, 512, FilterKind::Box, 0.5f};
    scene.materials = {testing::makeLambert(Rgb(0.0f))};
    scene.meshes.push_back(testing::makeQuad({0.9f, -1, -1}, {0, 0, 3}, {0, 3, 0}, 0));  // normal -x
    scene.mediumNames = {"glow"};
    scene.cameraMedium = 0;
    lookNarrowly(scene, {0.1f, 0.5f, 0.5f}, {1.0f, 0.5f, 0.5f});
}

template <typename Value>
SampledGrid<Value> uniformLattice(Value value) {
    SampledGrid<Value> grid{8, 3, 3, {}, {}};
    grid.values.assign(8 * 3 * 3, value);
    return grid;
}

// A temperature grid: the blackbody of pbrt-v4 (largest spectral value 1) at
// (T - offset) * scale = (1000 - 400) * 5 = 3000 K, times the emission scale 1.5.
TEST(Media, ATemperatureGridGlowsAsItsBlackbody) {
    const float sigmaA = 2.0f;
    GridMedium grid;
    grid.sigmaA = Rgb(sigmaA);
    grid.sigmaS = Rgb(0.0f);
    grid.density = uniformLattice(1.0f);
    grid.emission.temperature = uniformLattice(1000.0f);
    grid.emission.temperatureOffset = 400.0f;
    grid.emission.temperatureScale = 5.0f;
    grid.emission.scale = 1.5f;
    grid.buildMajorants();
    Scene scene;
    scene.media.push_back(grid);
    lookAlongXAtABlackWall(scene);
    const Rgb le = blackbodyPeakNormalizedRgb(3000.0) * 1.5f;
    for (int c = 0; c < 3; ++c) {
        const double exact = le[c] * (1.0 - std::exp(-double(sigmaA) * kEmissionPath));
        const PixelMean m = renderedChannelMean(scene, c);
        EXPECT_TRUE(withinSigmas(m.mean, exact, m.standardError))
            << "channel " << c << ": " << m.mean << " vs " << exact;
    }
}

// An RGB grid: chromatic absorption and emission lattices (pbrt-v4's rgbgrid), each channel its own
// closed form, through spectral MIS over the per-channel majorants.
TEST(Media, AnRgbGridGlowsAndAbsorbsPerChannel) {
    const Rgb sigmaA(0.5f, 1.0f, 3.0f), le(1.0f, 2.0f, 3.0f);
    RgbGridMedium grid;
    grid.sigmaA = uniformLattice(sigmaA);
    grid.emission = uniformLattice(le);
    grid.emissionScale = 0.5f;
    grid.buildMajorants();
    Scene scene;
    scene.media.push_back(grid);
    lookAlongXAtABlackWall(scene);
    for (int c = 0; c < 3; ++c) {
        const double exact = 0.5 * le[c] * (1.0 - std::exp(-double(sigmaA[c]) * kEmissionPath));
        for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
            const PixelMean m = renderedChannelMean(scene, c, accelerator);
            EXPECT_TRUE(withinSigmas(m.mean, exact, m.standardError))
                << "channel " << c << ": " << m.mean << " vs " << exact;
        }
    }
}

// A procedural cloud (pbrt-v4's `cloud`): delta tracking through its noise density along a line at
// y = 0.3 of its unit box, against the transmittance exp(-sigma_t * integral of the density),
// the integral by Simpson's rule in 2^14 steps of the density function (continuous: the
// quadrature's error is far below the test's). Also its base: with "density" 0 the noise drops out
// and the density is 1 - 2y below y = 0.5, so a vertical ray sees sigma_t / 4 of optical depth.
TEST(Media, DeltaTrackingThroughACloudMatchesTheIntegralOfItsDensity) {
    auto transmittanceAlongX = [](const CloudMedium& cloud, float y, float z) {
        const double depth = simpson(
            [&](double x) {
                return double(cloud.densityAt({float(x), y, z}));
            },
            0.0, 1.0, 1 << 14);
        return std::exp(-double(cloud.sigmaA.r + cloud.sigmaS.r) * depth);
    };
    auto rendered = [](const CloudMedium& cloud, Vec3f from, Vec3f to) {
        Scene scene;
        scene.film = {16, 16, 512, FilterKind::Box, 0.5f};
        scene.environment = EnvironmentLight::constant(Rgb(1.0f));
        scene.media.push_back(cloud);
        scene.mediumNames = {"cloud"};
        scene.cameraMedium = 0;
        lookNarrowly(scene, from, to, {0.0f, 0.0f, 1.0f});
        return renderedChannelMean(scene, 0);
    };
    CloudMedium cloud;
    cloud.sigmaA = Rgb(3.0f);
    cloud.sigmaS = Rgb(0.0f);
    cloud.buildMajorants();
    const double exact = transmittanceAlongX(cloud, 0.3f, 0.4f);
    EXPECT_GT(exact, 0.05);
    EXPECT_LT(exact, 0.95);
    const PixelMean m = rendered(cloud, {-1.0f, 0.3f, 0.4f}, {2.0f, 0.3f, 0.4f});
    EXPECT_TRUE(withinSigmas(m.mean, exact, m.standardError)) << m.mean << " vs " << exact;

    cloud.density = 0.0f;
    const PixelMean base = rendered(cloud, {0.3f, -1.0f, 0.4f}, {0.3f, 2.0f, 0.4f});
    EXPECT_TRUE(withinSigmas(base.mean, std::exp(-3.0 / 4.0), base.standardError)) << base.mean;
}

}  // namespace
}  // namespace penumbra
