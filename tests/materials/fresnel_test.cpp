// Fresnel reflectance and the specular directions against closed forms and against an independent
// formulation (Hecht's angle forms, in double). Tolerances are float accuracy: the formulas take a
// few dozen float operations on values of order 1, so 1e-5 absolute holds with a wide margin and
// any wrong factor or sign shows as an error of order 1e-2 or more.
#include "materials/fresnel.h"

#include <gtest/gtest.h>

#include <cmath>

#include "materials/dielectric.h"
#include "tests/support/bsdf_test_support.h"

namespace penumbra {
namespace {

using test::kPiD;

TEST(Fresnel, NormalIncidenceIsTheClosedForm) {
    for (float eta : {1.0f, 1.33f, 1.5f, 2.42f, 0.75f}) {
        const double expected = std::pow((eta - 1.0) / (eta + 1.0), 2.0);
        EXPECT_NEAR(fresnelDielectric(1.0f, eta), expected, 1e-6) << eta;
        EXPECT_NEAR(fresnelDielectric(-1.0f, 1.0f / eta), expected, 1e-6) << eta;  // from the other side
        EXPECT_NEAR(fresnelSchlick(1.0f, eta), expected, 1e-6) << eta;
    }
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.5f), 0.04, 1e-7);  // the familiar 4% of glass
}

TEST(Fresnel, MatchesHechtsAngleFormAtEveryAngle) {
    for (float eta : {1.33f, 1.5f, 2.42f, 1.0f / 1.5f})
        for (int i = 0; i <= 900; ++i) {
            const double theta = i * 0.1 * kPiD / 180.0;
            const float cosTheta = float(std::cos(theta));
            EXPECT_NEAR(fresnelDielectric(cosTheta, eta), test::fresnelHecht(cosTheta, eta), 1e-5)
                << "eta " << eta << " theta " << i * 0.1;
        }
}

TEST(Fresnel, TotalInternalReflectionBeyondTheCriticalAngle) {
    const float eta = 1.5f;
    const double critical = std::asin(1.0 / eta) * 180.0 / kPiD;  // 41.81 degrees
    for (double theta = 0.0; theta <= 90.0; theta += 0.25) {
        // Light inside the glass arriving at theta: the relative index eta_t / eta_i is 1 / 1.5.
        const float cosTheta = float(std::cos(theta * kPiD / 180.0));
        const float inside = fresnelDielectric(cosTheta, 1.0f / eta);
        const float schlick = fresnelSchlick(cosTheta, 1.0f / eta);
        if (theta > critical + 1e-3) {
            EXPECT_EQ(inside, 1.0f) << theta;
            EXPECT_EQ(schlick, 1.0f) << theta;
            EXPECT_FALSE(refractAcrossZ({float(std::sin(theta * kPiD / 180.0)), 0.0f, cosTheta}, 1.0f / eta)
                             .has_value());
        } else if (theta < critical - 1e-3) {
            EXPECT_LT(inside, 1.0f) << theta;
            EXPECT_TRUE(refractAcrossZ({float(std::sin(theta * kPiD / 180.0)), 0.0f, cosTheta}, 1.0f / eta)
                            .has_value());
        }
        // Reciprocity of the interface: the reflectance from inside at theta equals that from
        // outside at the refracted angle.
        if (theta < critical - 1e-3) {
            const double sinOutside = std::sin(theta * kPiD / 180.0) * eta;
            const float cosOutside = float(std::sqrt(1.0 - sinOutside * sinOutside));
            EXPECT_NEAR(inside, fresnelDielectric(cosOutside, eta), 2e-4)
                << theta;  // steep near the critical angle
        }
    }
    // Reflectance rises continuously to 1 at the critical angle.
    EXPECT_GT(fresnelDielectric(float(std::cos((critical - 0.01) * kPiD / 180.0)), 1.0f / eta), 0.8f);
}

TEST(Fresnel, BrewsterAngleKillsTheParallelPolarization) {
    const double eta = 1.5, brewster = std::atan(eta);
    const double thetaT = std::asin(std::sin(brewster) / eta);
    const double rs = std::sin(brewster - thetaT) / std::sin(brewster + thetaT);
    EXPECT_NEAR(fresnelDielectric(float(std::cos(brewster)), float(eta)), 0.5 * rs * rs, 1e-6);
}

TEST(Fresnel, SchlickIsCloseToExactAndExactAtTheEnds) {
    double worst = 0.0;
    for (int i = 0; i <= 90; ++i) {
        const float cosTheta = float(std::cos(i * kPiD / 180.0));
        worst = std::max(
            worst, double(std::abs(fresnelSchlick(cosTheta, 1.5f) - fresnelDielectric(cosTheta, 1.5f))));
    }
    // Schlick's approximation of glass is off by up to 0.036 (near 80 degrees, where the exact
    // curve rises steeply) and much less elsewhere; a wrong exponent or R0 is off by more.
    EXPECT_LT(worst, 0.04);
    EXPECT_GT(worst, 0.02);
    EXPECT_NEAR(fresnelSchlick(0.0f, 1.5f), 1.0f, 1e-6);
}

TEST(Fresnel, ConductorClosedFormsAndLimits) {
    struct Metal {
        float n, k;
    };
    for (Metal m : {Metal{0.2f, 3.9f}, Metal{1.4f, 1.6f}, Metal{2.9f, 3.0f}}) {
        const double expected =
            ((m.n - 1.0) * (m.n - 1.0) + m.k * m.k) / ((m.n + 1.0) * (m.n + 1.0) + m.k * m.k);
        EXPECT_NEAR(fresnelComplex(1.0f, {m.n, m.k}), expected, 1e-6);
        EXPECT_NEAR(fresnelComplex(0.0f, {m.n, m.k}), 1.0, 1e-6);  // grazing incidence reflects all
    }
    // k = 0 is a dielectric.
    for (int i = 0; i <= 90; i += 5) {
        const float cosTheta = float(std::cos(i * kPiD / 180.0));
        EXPECT_NEAR(fresnelComplex(cosTheta, {1.5f, 0.0f}), fresnelDielectric(cosTheta, 1.5f), 1e-6) << i;
    }
}

TEST(Refraction, SnellsLawAndReversibility) {
    for (float eta : {1.5f, 1.0f / 1.5f, 1.33f})
        for (double theta = 0.0; theta < 89.0; theta += 7.0)
            for (float side : {1.0f, -1.0f}) {
                const double t = theta * kPiD / 180.0, phi = 0.7;
                const Vec3f w{float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)),
                              side * float(std::cos(t))};
                const auto wt = refractAcrossZ(w, eta);
                if (std::sin(t) / eta >= 1.0) {
                    EXPECT_FALSE(wt.has_value());
                    continue;
                }
                ASSERT_TRUE(wt.has_value());
                EXPECT_LT(wt->z * w.z, 0.0f);
                EXPECT_NEAR(length(*wt), 1.0f, 1e-6f);
                EXPECT_NEAR(std::hypot(wt->x, wt->y) * eta, std::sin(t), 1e-6);
                // Going back through the interface returns the original direction.
                const auto back = refractAcrossZ(*wt, 1.0f / eta);
                ASSERT_TRUE(back.has_value());
                EXPECT_NEAR(back->x, w.x, 1e-6f);
                EXPECT_NEAR(back->y, w.y, 1e-6f);
                EXPECT_NEAR(back->z, w.z, 1e-6f);
            }
}

// The glass sample's reflectance is decided by the geometric side: the same local wo gives the
// entering reflectance on the front and the leaving one on the back (total internal reflection
// included), whatever the shading frame says.
TEST(Dielectric, SideComesFromTheCaller) {
    Dielectric glass;
    glass.eta = 1.5f;
    const Vec3f wo = test::directionFromAngles(60.0, 0.0);
    EXPECT_NEAR(glass.reflectance(wo, true), fresnelDielectric(0.5f, 1.5f), 1e-7);
    EXPECT_EQ(glass.reflectance(wo, false), 1.0f);  // 60 degrees inside glass is beyond the critical angle
    const auto inside = glass.sample(wo, 0.999f, {}, false);
    ASSERT_TRUE(inside.has_value());
    EXPECT_FALSE(inside->isTransmission());
    const auto outside = glass.sample(wo, 0.999f, {}, true);
    ASSERT_TRUE(outside.has_value());
    EXPECT_TRUE(outside->isTransmission());
    EXPECT_NEAR(outside->weight.r, 1.0f / 2.25f, 1e-6f);  // radiance entering glass is scaled by 1 / eta^2
}

}  // namespace
}  // namespace penumbra
