// The goniometric light (lights/goniometric_light.h) read from a scene file with an IES profile
// (tests/data/ies/quadrant_2002.ies: LM-63-2002, quadrant symmetry, candela x 1.5) at height h over
// a Lambert plane of albedo a. The radiance leaving the plane at a point at distance d from the
// light, seen from it at vertical angle theta and horizontal angle phi, is
//   L = (a / pi) * I(theta, phi) * cos(theta) / d^2,
// with I the file's candela values (at the table's angles; bilinear between them). The camera
// looks straight down at the point with a footprint of +-0.44% of its height, as in
// point_light_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/sampling.h"
#include "lights/light_set.h"
#include "scenes/scene_loader.h"
#include "tests/support/rendered_mean.h"

namespace penumbra {
namespace {

const std::filesystem::path kIesFolder = std::filesystem::path(PENUMBRA_TEST_DATA_DIR) / "ies";

using testing::renderedMeanAt;

// A plane at y = 0 and a goniometric light at height 2 pointing down, its horizontal angle 0
// towards +x: by LM-63's counterclockwise angles seen from above, angle 90 lies towards -z.
Scene planeUnderProfile(const std::string& file, const std::string& extraKeys = "") {
    const std::string json = R"({
        "film": {"resolution": [8, 8], "spp": 16, "filter": {"type": "box", "radius": 0.5}},
        "camera": {"fov": 0.5},
        "integrator": {"max_depth": 1},
        "materials": {"white": {"type": "lambert", "albedo": 0.6}},
        "shapes": [{"type": "quad", "corner": [-50, 0, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0],
                    "material": "white"}],
        "lights": [{"type": "goniometric", "position": [0, 2, 0], "file": ")" +
                             file + R"(", "front": [1, 0, 0])" + extraKeys + R"(}]
    })";
    return parseScene(json, kIesFolder / "scene.json");
}

// The point of the plane seen from the light at (theta, phi) in degrees.
Vec3f planePointAt(double thetaDegrees, double phiDegrees) {
    const double theta = thetaDegrees * kPi / 180.0, phi = phiDegrees * kPi / 180.0;
    const double radius = 2.0 * std::tan(theta);
    return {float(radius * std::cos(phi)), 0.0f, float(-radius * std::sin(phi))};
}

double expectedRadiance(double candela, double thetaDegrees, double scale = 1.0) {
    const double cosTheta = std::cos(thetaDegrees * kPi / 180.0);
    const double distanceSquared = 4.0 / (cosTheta * cosTheta);
    return 0.6 / kPi * scale * candela * cosTheta / distanceSquared;
}

TEST(GoniometricLight, PlaneRadianceFollowsTheProfilesCandelaValues) {
    const Scene scene = planeUnderProfile("quadrant_2002.ies");
    // The file's values (times its multipliers 2 x 0.75) at table angles, in each quadrant that
    // the symmetry unfolds, and the mean of four values midway between table angles. At table
    // angles the bilinear profile has a kink, which the footprint averages to first order: 2e-3.
    struct Case {
        double theta, phi, candela, tolerance;
    };
    for (const Case& c :
         {Case{45, 0, 80 * 1.5, 2e-3}, Case{45, 30, 90 * 1.5, 2e-3}, Case{45, 90, 100 * 1.5, 2e-3},
          Case{45, 150, 90 * 1.5, 2e-3}, Case{45, 270, 100 * 1.5, 2e-3}, Case{45, 330, 90 * 1.5, 2e-3},
          Case{67.5, 60, (90 + 30 + 100 + 40) / 4.0 * 1.5, 2e-3},
          Case{22.5, 15, (100 + 80 + 120 + 90) / 4.0 * 1.5, 2e-3}}) {
        const double expected = expectedRadiance(c.candela, c.theta);
        EXPECT_NEAR(renderedMeanAt(planePointAt(c.theta, c.phi), scene), expected, c.tolerance * expected)
            << "theta " << c.theta << ", phi " << c.phi;
    }
}

TEST(GoniometricLight, HorizontalAnglesTurnCounterclockwiseSeenFromAbove) {
    // full_2002.ies has no symmetry: at vertical angle 30 it gives 21 cd at horizontal angle 60 and
    // 24 cd at 300, which a mirrored profile would swap.
    const Scene scene = planeUnderProfile("full_2002.ies");
    for (const auto& [phi, candela] : {std::pair{60.0, 21.0}, std::pair{300.0, 24.0}}) {
        const double expected = expectedRadiance(candela, 30.0);
        EXPECT_NEAR(renderedMeanAt(planePointAt(30.0, phi), scene), expected, 2e-3 * expected)
            << "phi " << phi;
    }
}

TEST(GoniometricLight, ScaleAndNadirPlaceTheProfile) {
    // Pointing up, the profile's lower hemisphere (vertical 0..90) lights nothing below it.
    const Scene up = planeUnderProfile("quadrant_2002.ies", R"(, "nadir": [0, 1, 0])");
    EXPECT_EQ(renderedMeanAt(planePointAt(45, 0), up), 0.0);
    const Scene scaled = planeUnderProfile("isotropic_2002.ies", R"(, "scale": 0.25)");
    const double expected = expectedRadiance(100.0, 30.0, 0.25);
    EXPECT_NEAR(renderedMeanAt(planePointAt(30, 200), scaled), expected, 2e-4 * expected);
}

TEST(GoniometricLight, PowerIsTheProfileIntegratedOverTheSphere) {
    const Scene scene = planeUnderProfile("quadrant_2002.ies", R"(, "scale": [1, 2, 3])");
    const auto& light = std::get<GoniometricLight>(scene.lights.at(0));
    // Midpoint quadrature in (cos(theta), phi), uniform in solid angle, of the light's intensity.
    const int n = 1000;
    double flux = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            const double cosTheta = 1.0 - 2.0 * (i + 0.5) / n, phi = 2.0 * kPi * (j + 0.5) / (2 * n);
            const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
            const Vec3f w{float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)), float(cosTheta)};
            flux += light.intensity(w).luminance();
        }
    flux *= 4.0 * kPi / (2.0 * n * n);
    EXPECT_NEAR(light.power(1.0), flux, 1e-3 * flux);
}

TEST(GoniometricLight, ChosenInProportionToItsPower) {
    // 16 point lights and the goniometric one, chosen by power (LightSampler::Power; with more
    // emitters than LightSet weighs one by one, the default chooses through a tree): 4 pi I for a point
    // light, 4 pi x 100 cd x scale for the isotropic profile. Chi-square of 200000 choices against those
    // shares.
    Scene scene = planeUnderProfile("isotropic_2002.ies", R"(, "scale": 0.05)");
    std::vector<double> expectedShare;
    for (int i = 0; i < 16; ++i) {
        scene.lights.push_back(PointLight{{float(i), 3.0f, 0.0f}, Rgb(1.0f + 0.5f * float(i))});
        expectedShare.push_back(4.0 * kPi * (1.0 + 0.5 * i));
    }
    const double goniometricPower = 4.0 * kPi * 100.0 * 0.05;
    const LightSet lights(scene, scene.lights, scene.environment, LightSampler::Power);
    ASSERT_FALSE(lights.choosesLocally());
    ASSERT_EQ(lights.size(), 17u);
    // The light set puts the goniometric light after the point lights (the variant's order).
    expectedShare.push_back(goniometricPower);
    double total = 0.0;
    for (double p : expectedShare) total += p;
    std::vector<int> counts(17, 0);
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int draws = 200000;
    for (int i = 0; i < draws; ++i) {
        Vec2f uPoint{u(rng), u(rng)};
        ++counts.at(lights.choose(uPoint, {0, 0, 0}, {0, 1, 0}).light);
    }
    ASSERT_TRUE(std::holds_alternative<GoniometricLight>(lights.light(16)));
    double chiSquare = 0.0;
    for (size_t i = 0; i < counts.size(); ++i) {
        const double expected = draws * expectedShare[i] / total;
        chiSquare += (counts[i] - expected) * (counts[i] - expected) / expected;
    }
    // 16 degrees of freedom: the 0.999 quantile is 39.25.
    EXPECT_LT(chiSquare, 39.25);
}

TEST(GoniometricLight, EveryLayoutOfTheFixturesRendersAPositiveImage) {
    for (const char* file :
         {"lm63_1986.ies", "lm63_1991.ies", "bilateral_1995.ies", "cosine_1995.ies", "quadrant_2002.ies",
          "bilateral_90_270_2002.ies", "full_2002.ies", "isotropic_2002.ies"}) {
        // bilateral_1995.ies lights only its upper hemisphere (vertical 90..180): turned over.
        const bool upper = std::string(file) == "bilateral_1995.ies";
        const Scene scene = planeUnderProfile(file, upper ? R"(, "nadir": [0, 1, 0])" : "");
        const double mean = renderedMeanAt(planePointAt(30, 40), scene);
        EXPECT_TRUE(std::isfinite(mean) && mean > 0.0) << file << ": " << mean;
    }
}

TEST(GoniometricLight, AMissingOrMalformedProfileIsRefusedWithItsPlace) {
    try {
        planeUnderProfile("no-such.ies");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/lights/0/file"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    const auto folder = std::filesystem::temp_directory_path() / "penumbra-goniometric-test";
    std::filesystem::create_directories(folder);
    const auto bad = folder / "bad.ies";
    {
        std::ofstream out(bad);
        out << "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 90 180\n0\n100 -5 100\n";
    }
    try {
        planeUnderProfile(bad.string());
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.ies:7"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace penumbra
