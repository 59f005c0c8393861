// The subsurface material's albedo inversion (materials/subsurface_albedo.h) against the classical
// dipole's closed form: its end points, its monotonicity, round trips, and the diffuse Fresnel
// reflectance it takes against the polynomial fit Jensen et al. 2001 print.
#include "materials/subsurface_albedo.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

TEST(SubsurfaceAlbedo, TheDipoleReflectanceRisesFromZeroToOne) {
    for (double eta : {1.0, 1.33, 1.5, 2.0}) {
        const double internal = diffuseFresnelReflectance(1.0 / eta);
        EXPECT_DOUBLE_EQ(dipoleDiffuseReflectance(0.0, internal), 0.0);
        EXPECT_DOUBLE_EQ(dipoleDiffuseReflectance(1.0, internal), 1.0);
        double previous = 0.0;
        for (int i = 1; i <= 1000; ++i) {
            const double r = dipoleDiffuseReflectance(i / 1000.0, internal);
            EXPECT_GT(r, previous) << eta << " " << i;
            previous = r;
        }
        // A boundary that reflects light back in (A > 1) lets less out.
        if (eta > 1.0) {
            EXPECT_LT(dipoleDiffuseReflectance(0.9, internal), dipoleDiffuseReflectance(0.9, 0.0));
        }
    }
    // Index-matched: A = 1, R_d(a) = a / 2 (1 + exp(-4/3 s)) exp(-s), s = sqrt(3 (1 - a)).
    const double s = std::sqrt(3.0 * 0.25);
    EXPECT_NEAR(dipoleDiffuseReflectance(0.75, 0.0), 0.375 * (1 + std::exp(-4.0 / 3.0 * s)) * std::exp(-s),
                1e-15);
}

TEST(SubsurfaceAlbedo, InversionRoundTrips) {
    for (double eta : {1.0, 1.33, 1.6}) {
        const double internal = diffuseFresnelReflectance(1.0 / eta);
        for (int i = 0; i <= 100; ++i) {
            const double reflectance = i / 100.0;
            const double albedo = albedoForDiffuseReflectance(reflectance, eta);
            EXPECT_GE(albedo, 0.0);
            EXPECT_LE(albedo, 1.0);
            EXPECT_NEAR(dipoleDiffuseReflectance(albedo, internal), reflectance, 1e-12) << eta << " " << i;
        }
    }
    // Outside [0, 1]: clamped.
    EXPECT_DOUBLE_EQ(albedoForDiffuseReflectance(-1.0, 1.33), albedoForDiffuseReflectance(0.0, 1.33));
    EXPECT_DOUBLE_EQ(albedoForDiffuseReflectance(2.0, 1.33), albedoForDiffuseReflectance(1.0, 1.33));
}

// Jensen et al. 2001 take F_dr from the fit -1.440 / eta^2 + 0.710 / eta + 0.668 + 0.0636 eta (of
// light inside a medium of relative index eta); the exact integral agrees within the fit's error.
TEST(SubsurfaceAlbedo, TheInternalReflectanceIsTheOneJensenFits) {
    for (double eta : {1.2, 1.33, 1.5, 1.8}) {
        const double fit = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
        EXPECT_NEAR(diffuseFresnelReflectance(1.0 / eta), fit, 0.01) << eta;
    }
}

}  // namespace
}  // namespace penumbra
