// The colour of light (core/colorimetry.h): Planck's law against a value worked by hand, the
// matching functions' normalization, and the blackbody table against the exact integral it stands in
// for.
#include "core/colorimetry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

// B(500 nm, 6000 K) = 2 h c^2 / lambda^5 / (exp(h c / (lambda k T)) - 1): h c / (lambda k T) =
// 4.7959, exp of it minus 1 = 120.01, 2 h c^2 = 1.19105e-16 W m^2 / sr, lambda^5 = 3.125e-32 m^5:
// 3.1758e13 W / (sr m^2 m).
TEST(Colorimetry, PlanckRadianceMatchesAValueWorkedByHand) {
    EXPECT_NEAR(planckRadiance(500.0, 6000.0) / 3.1758e13, 1.0, 1e-3);
}

// A spectrum of constant value 1 has Y = 1, and the equal-energy white (x = y = 1/3 by the
// definition of CIE XYZ) comes out with x and y within the fit's 1% of 1/3.
TEST(Colorimetry, TheConstantSpectrumHasUnitLuminance) {
    const Xyz xyz = spectrumToXyz([](double) { return 1.0; });
    EXPECT_NEAR(xyz[1], 1.0, 1e-12);
    const double sum = xyz[0] + xyz[1] + xyz[2];
    EXPECT_NEAR(xyz[0] / sum, 1.0 / 3.0, 0.01);
    EXPECT_NEAR(xyz[1] / sum, 1.0 / 3.0, 0.01);
}

// pbrt-v4's BlackbodySpectrum is the unit-luminance blackbody times the luminance of Planck's law
// divided by its peak (Wien: lambda_max = 2.8977721e-3 m K / T).
TEST(Colorimetry, ThePeakNormalizedBlackbodyIsTheUnitLuminanceOneScaled) {
    for (double kelvin : {1500.0, 3000.0, 6500.0, 20000.0}) {
        const double peak = planckRadiance(2.8977721e-3 / kelvin * 1e9, kelvin);
        const double luminance = spectrumToXyz([&](double l) { return planckRadiance(l, kelvin) / peak; })[1];
        const Rgb expected = blackbodyRgb(kelvin) * float(luminance);
        const Rgb got = blackbodyPeakNormalizedRgb(kelvin);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], expected[c], 1e-5 * expected.maxComponent()) << kelvin;
    }
}

// The table errs by under 1e-4 of the colour's largest channel from 1000 K up (its step is 1/800 in
// ln T; see colorimetry.cpp), and is black at and below 0 K and for NaN.
TEST(Colorimetry, TheBlackbodyTableFollowsTheExactIntegral) {
    for (double kelvin = 1000.0; kelvin < 1e6; kelvin *= 1.0137) {
        const Rgb exact = blackbodyPeakNormalizedRgb(kelvin);
        const Rgb table = blackbodyPeakNormalizedRgbTabulated(float(kelvin));
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(table[c], exact[c], 1e-4 * exact.maxComponent()) << kelvin << " K, channel " << c;
    }
    EXPECT_TRUE(blackbodyPeakNormalizedRgbTabulated(0.0f).isBlack());
    EXPECT_TRUE(blackbodyPeakNormalizedRgbTabulated(-5.0f).isBlack());
    EXPECT_TRUE(blackbodyPeakNormalizedRgbTabulated(std::nanf("")).isBlack());
    EXPECT_TRUE(blackbodyPeakNormalizedRgbTabulated(1e30f).isFinite());
}

}  // namespace
}  // namespace penumbra
