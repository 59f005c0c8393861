// The materials inside the path tracer, against closed forms: white furnaces (objects in a
// uniform environment of radiance L), the invisibility of a non-absorbing glass sphere, the
// radiance scale eta^2 seen from inside glass, Beer-Lambert absorption through a slab with the
// Fresnel reflections at its two faces, and one-sided materials.
//
// Tolerances. The image mean of a render is compared with the exact value within 5 standard
// errors, the standard error coming from the film's per-pixel sums of squares (pixels are
// independent; stratification only lowers the true error, so the bound is conservative). A false
// failure has probability below 1e-6 per check. Renders whose every path has the same value (the
// glass and mirror furnaces: every event has weight exactly 1) have a standard error of ~0; for
// them the floor is float rounding of the throughput products, well below 1e-4 relative for paths
// of a few dozen events. Where the camera sees a small range of angles, the value's variation over
// the field of view (0.25 degrees) is second order and below 5e-5 relative.
#include <gtest/gtest.h>

#include <cmath>

#include "film/film.h"
#include "renderer/render.h"
#include "tests/support/bsdf_test_support.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

struct ImageMean {
    double mean[3] = {0, 0, 0};
    double standardError[3] = {0, 0, 0};
    RenderStats stats;
};

ImageMean renderMean(const Scene& scene) {
    Film film(scene.film.width, scene.film.height);
    ImageMean result;
    result.stats = render(scene, RenderOptions{}, film);
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sumSquares = 0, count = 0;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x) {
                sum += film.at(x, y).radiance[c];
                sumSquares += film.at(x, y).radianceSquared[c];
                count += film.at(x, y).weight;
            }
        result.mean[c] = sum / count;
        result.standardError[c] =
            std::sqrt(std::max(0.0, sumSquares / count - result.mean[c] * result.mean[c]) / count);
    }
    return result;
}

void expectMean(const ImageMean& image, Rgb expected, double relativeFloor, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(image.mean[c], expected[c],
                    5.0 * image.standardError[c] + relativeFloor * expected[c] + 1e-7)
            << what << ", channel " << c << " (standard error " << image.standardError[c] << ")";
}

// A unit sphere at the origin, seen from (0, 0, 4) with a field of view narrower than the sphere
// (it subtends 14.5 degrees around the axis, the image's corners lie 11.3 degrees off it).
Scene sphereFurnace(const Material& material, float background) {
    Scene scene;
    scene.film = {16, 16, 64, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0.0f, 0.0f, 4.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 16.0f;
    scene.integrator.maxDepth = 10000;  // truncation: the chance of 10000 internal reflections is nil
    scene.settings.seed = 3;
    scene.environment = EnvironmentLight::constant(Rgb(background));
    scene.materials = {material};
    Sphere sphere;
    sphere.radius = 1.0f;
    scene.spheres.push_back(sphere);
    return scene;
}

// A 20 x 20 quad in the plane z = 0 (front +z), seen from distance 2 at polar angle thetaDegrees
// through a 0.25 degree field of view, so that every pixel sees (almost) the same wo.
Scene quadFurnace(const Material& material, float background, double thetaDegrees, bool fromBehind = false) {
    Scene scene;
    scene.film = {8, 8, 256, FilterKind::Box, 0.5f};
    const double t = test::radians(thetaDegrees);
    scene.camera.lookFrom = {float(2.0 * std::sin(t)), 0.0f, float((fromBehind ? -2.0 : 2.0) * std::cos(t))};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 0.25f;
    scene.integrator.maxDepth = 1000;
    scene.settings.seed = 11;
    scene.environment = EnvironmentLight::constant(Rgb(background));
    scene.materials = {material};
    scene.meshes.push_back(testing::makeQuad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, 0));
    return scene;
}

// ---- White furnaces ----

TEST(WhiteFurnace, AlbedoOneLambertSphereReturnsTheEnvironment) {
    const Material m(Lambert{Rgb(1.0f)});
    expectMean(renderMean(sphereFurnace(m, 0.7f)), Rgb(0.7f), 1e-4, "lambert");
}

// Diffuse transmission with R + T = 1 loses nothing: light leaves the sphere after any number of
// bounces inside and out, and the sphere disappears into the furnace, as it does with R + T < 1
// darkened by exactly what a closed form gives for a flat quad (albedo R + T at every angle).
TEST(WhiteFurnace, DiffuseTransmissionConservesWhatItReflectsAndTransmits) {
    const Material white(DiffuseTransmission{{0.7f, 0.5f, 0.2f}, {0.3f, 0.5f, 0.8f}});
    expectMean(renderMean(sphereFurnace(white, 0.7f)), Rgb(0.7f), 1e-4, "diffuse transmission sphere");
    const Material grey(DiffuseTransmission{{0.4f, 0.1f, 0.3f}, {0.2f, 0.5f, 0.1f}});
    // A plane sees no other surface: it returns R + T of the environment, seen from either side.
    expectMean(renderMean(quadFurnace(grey, 1.0f, 40.0)), {0.6f, 0.6f, 0.4f}, 1e-4,
               "diffuse transmission quad");
    expectMean(renderMean(quadFurnace(grey, 1.0f, 70.0, true)), {0.6f, 0.6f, 0.4f}, 1e-4,
               "diffuse transmission quad from behind");
}

// A mix shades one of its two materials at each point, the second with probability `amount`: on a
// plane in a furnace each Lambert returns its albedo, so the mix returns the blend of the two
// albedos, and with a checkerboard amount each square returns its own material's.
TEST(WhiteFurnace, MixReturnsTheBlendOfItsMaterials) {
    const Rgb red{0.8f, 0.2f, 0.1f}, blue{0.1f, 0.3f, 0.9f};
    Scene scene = quadFurnace(Material(Lambert{red}), 1.0f, 30.0);
    scene.materials.push_back(Material(Lambert{blue}));
    scene.materials.push_back(Material::mixOf({0, 1, 0.3f, nullptr}));
    scene.meshes[0].material = 2;
    expectMean(renderMean(scene), red * 0.7f + blue * 0.3f, 1e-4, "mix of two lamberts, amount 0.3");
    scene.materials[2] = Material::mixOf({0, 1, 1.0f, nullptr});
    expectMean(renderMean(scene), blue, 0.0, "amount 1: the second");
}

TEST(WhiteFurnace, WhiteMirrorSphereReturnsTheEnvironment) {
    const Material m(Mirror{});
    const ImageMean image = renderMean(sphereFurnace(m, 1.3f));
    expectMean(image, Rgb(1.3f), 1e-4, "mirror");
    EXPECT_EQ(image.stats.rays.shadow, 0u);  // no next-event estimation on purely specular surfaces
}

// Phong with kd + ks = 1 returns at most the environment; what it loses is the part of the
// specular lobe that the horizon clips, ks (1 - E(theta)), with E from phongSpecularAlbedo (an
// independent 1D integral).
TEST(WhiteFurnace, PhongLosesExactlyTheClippedLobe) {
    for (float n : {1.0f, 10.0f, 100.0f})
        for (double theta : {0.0, 60.0, 80.0}) {
            const Material m(Phong{Rgb(0.3f), Rgb(0.7f), n});
            const double expected = 0.3 + 0.7 * test::phongSpecularAlbedo(n, test::radians(theta));
            EXPECT_LE(expected, 1.0 + 1e-9);
            const ImageMean image = renderMean(quadFurnace(m, 1.0f, theta));
            expectMean(image, Rgb(float(expected)), 2e-4,
                       "phong n " + std::to_string(n) + " theta " + std::to_string(theta));
            EXPECT_LE(image.mean[1], 1.0 + 5.0 * image.standardError[1]);
            if (theta == 0.0) {
                EXPECT_NEAR(expected, 1.0, 1e-6);  // no clipping at normal incidence
            }
            if (theta == 80.0 && n <= 10.0f) {
                EXPECT_LT(expected, 0.9);  // and a visible loss at grazing angles
            }
        }
}

// A smooth conductor at normal incidence reflects ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) per channel.
TEST(WhiteFurnace, ConductorReflectsItsNormalIncidenceFresnel) {
    Conductor conductor;
    conductor.eta = {0.2f, 0.9f, 1.4f};
    conductor.k = {3.9f, 2.4f, 1.6f};
    const Material m(conductor);
    Rgb expected;
    for (int c = 0; c < 3; ++c) {
        const double n = conductor.eta[c], k = conductor.k[c];
        (c == 0   ? expected.r
         : c == 1 ? expected.g
                  : expected.b) = float(((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k));
    }
    expectMean(renderMean(quadFurnace(m, 1.0f, 0.0)), expected, 1e-4, "conductor");
}

// ---- Glass ----

// A non-absorbing dielectric sphere in a uniform environment is invisible: every path leaves it
// with weight 1 (1 / eta^2 entering, eta^2 leaving, 1 on each reflection). Exact and Schlick
// Fresnel, glass, water, and a sphere of lower index than outside (an air bubble in water).
TEST(Glass, NonAbsorbingSphereIsInvisible) {
    struct Case {
        float eta;
        FresnelModel fresnel;
    };
    for (const Case c : {Case{1.5f, FresnelModel::Exact}, Case{1.5f, FresnelModel::Schlick},
                         Case{1.33f, FresnelModel::Exact}, Case{0.75f, FresnelModel::Exact}}) {
        Dielectric dielectric;
        dielectric.eta = c.eta;
        dielectric.fresnel = c.fresnel;
        const Material m(dielectric);
        const ImageMean image = renderMean(sphereFurnace(m, 0.8f));
        expectMean(image, Rgb(0.8f), 1e-4, "eta " + std::to_string(c.eta));
        EXPECT_EQ(image.stats.rays.shadow, 0u);
    }
}

TEST(Glass, ThinDielectricSphereIsInvisible) {
    ThinDielectric thin;
    thin.eta = 1.5f;
    const Material m(thin);
    expectMean(renderMean(sphereFurnace(m, 0.8f)), Rgb(0.8f), 1e-4, "thin dielectric");
}

// Radiance, not importance: in equilibrium with an environment L, the radiance inside glass is
// eta^2 L (L / eta^2 is invariant along rays). A camera inside a glass sphere, 0.37 from its centre
// (so that no ray from it is trapped by total internal reflection: sin(theta) <= 0.37 < 1 / 1.5),
// sees eta^2 L in every direction.
TEST(Glass, CameraInsideGlassSeesEtaSquaredTimesTheEnvironment) {
    Dielectric dielectric;
    dielectric.eta = 1.5f;
    const Material m(dielectric);
    Scene scene = sphereFurnace(m, 0.5f);
    scene.camera.lookFrom = {0.3f, 0.2f, 0.1f};
    scene.camera.lookAt = {0.0f, 1.0f, -1.0f};
    scene.camera.verticalFovDegrees = 90.0f;
    expectMean(renderMean(scene), Rgb(0.5f * 1.5f * 1.5f), 1e-4, "inside glass");
}

// ---- Absorption ----

// A glass slab of thickness d (two large parallel faces, fronts facing out) seen at normal
// incidence in front of a uniform environment L. With R = ((eta - 1) / (eta + 1))^2 at each face
// and internal transmittance tau = exp(-sigma d), the light reaching the camera sums the front
// reflection and all paths through the slab (the environment is the same behind and in front):
//     L [R + (1 - R)^2 tau (1 + R tau) / (1 - R^2 tau^2)] = L [R + (1 - R)^2 tau / (1 - R tau)].
// sigma comes from "transmittance color after distance 1": sigma = -ln(color).
TEST(Absorption, SlabTransmittanceMatchesBeerLambertWithFresnel) {
    const Rgb color{0.2f, 0.5f, 0.9f};
    const float thickness = 1.5f, eta = 1.5f;
    Dielectric dielectric;
    dielectric.eta = eta;
    dielectric.absorption = {-std::log(color.r), -std::log(color.g), -std::log(color.b)};
    const Material m(dielectric);

    Scene scene;
    scene.film = {8, 8, 4096, FilterKind::Box, 0.5f};
    scene.camera.lookFrom = {0.0f, 0.0f, 5.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 0.25f;
    scene.integrator.maxDepth = 1000;
    scene.settings.seed = 5;
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    scene.materials = {m};
    scene.meshes.push_back(testing::makeQuad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0}, 0));  // front, +z
    scene.meshes.push_back(
        testing::makeQuad({-50, -50, -thickness}, {0, 100, 0}, {100, 0, 0}, 0));  // back, -z

    const double r = ((eta - 1.0) / (eta + 1.0)) * ((eta - 1.0) / (eta + 1.0));
    Rgb expected;
    for (int c = 0; c < 3; ++c) {
        const double tau = std::pow(double(color[c]), double(thickness));
        (c == 0   ? expected.r
         : c == 1 ? expected.g
                  : expected.b) = float(r + (1 - r) * (1 - r) * tau / (1 - r * tau));
    }
    const ImageMean image = renderMean(scene);
    expectMean(image, expected, 2e-4, "slab");
    // The test can fail: without absorption the slab would be invisible (1.0), and in the red
    // channel the answer that forgets the Fresnel factors (tau alone) is more than 10 standard
    // errors away.
    EXPECT_GT(std::abs(double(std::pow(color.r, thickness)) - expected.r), 10.0 * image.standardError[0]);
}

// ---- Sides ----

TEST(Sides, OneSidedLambertIsBlackFromBehindTwoSidedIsNot) {
    const Material oneSided(Lambert{Rgb(1.0f)}, false), twoSided(Lambert{Rgb(1.0f)}, true);
    expectMean(renderMean(quadFurnace(oneSided, 1.0f, 30.0, true)), Rgb(0.0f), 0.0, "one-sided, back");
    expectMean(renderMean(quadFurnace(oneSided, 1.0f, 30.0, false)), Rgb(1.0f), 1e-4, "one-sided, front");
    expectMean(renderMean(quadFurnace(twoSided, 1.0f, 30.0, true)), Rgb(1.0f), 1e-4, "two-sided, back");
}

}  // namespace
}  // namespace penumbra
