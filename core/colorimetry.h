// Light as the eye and the film see it: the CIE 1931 2-degree colour matching functions, XYZ to the
// linear Rec.709 (sRGB primaries, D65 white) RGB that penumbra renders in, and Planck's blackbody.
//
// The matching functions are the multi-lobe Gaussian fit of Wyman, Sloan and Shirley ("Simple
// Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2013), within about 1% of
// CIE 015:2004's tables over the visible range. A spectrum's XYZ is its Riemann sum at 1 nm from 360
// to 830 nm divided by that of y-bar, so a spectrum of constant value 1 has Y = 1 (pbrt-v4's film
// divides by CIE_Y_integral the same way).
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "core/rgb.h"

namespace penumbra {

using Xyz = std::array<double, 3>;

inline constexpr double kVisibleLambdaMin = 360.0, kVisibleLambdaMax = 830.0;  // nm

// x-bar, y-bar and z-bar at `lambda` nm.
Xyz cieMatching(double lambdaNm);
// cieMatching at 360, 361, ..., 830 nm, computed once.
const std::vector<Xyz>& cieMatchingAt1nm();
// The sum of y-bar over the 1 nm steps from 360 to 830 nm.
double cieYIntegral();
Rgb xyzToLinearSrgb(const Xyz& xyz);
// Its inverse (Lindbloom's sRGB to XYZ matrix, D65).
Xyz linearSrgbToXyz(Rgb c);
// The chromaticity (x, y) of penumbra's white, D65 (CIE 015:2004).
constexpr std::array<double, 2> kD65Chromaticity{0.31271, 0.32902};
// The chromaticity of CIE daylight at correlated colour temperature `kelvin`: the CIE daylight
// locus (CIE 015:2004, eq. 3.3 and 3.4) from 4000 K to 25000 K (clamped above), at the
// temperature corrected from the old radiation constant c2 = 1.4380e-2 to 1.4388e-2 m K (as
// pbrt-v4's Spectra::D), and below 4000 K, where daylight is not defined, a blackbody's (the
// Planckian locus, Kim et al.'s cubics).
std::array<double, 2> daylightChromaticity(double kelvin);
// A von Kries white balance (pbrt-v4's WhiteBalance): the 3 x 3 matrix on XYZ that takes the white of
// chromaticity `from` to the white of chromaticity `to`, scaling the Bradford cone responses.
std::array<Xyz, 3> whiteBalanceXyz(std::array<double, 2> from, std::array<double, 2> to);
// The colour of `xyz` scaled to luminance Y = 1 (black where Y is not positive).
Rgb unitLuminanceLinearSrgb(const Xyz& xyz);
// The colour of a reflectance spectrum from its spectrumToXyz (the XYZ it has under an equal-energy
// light) as seen under penumbra's D65 white: the Bradford transform from the equal-energy white to
// D65 (Lam 1985, as in CIECAM97s), then xyzToLinearSrgb, scaled so that a flat reflectance c is
// exactly (c, c, c).
Rgb reflectanceXyzToLinearSrgb(const Xyz& xyzUnderEqualEnergy);

// The sum of spectrum(lambda) times the matching functions over the 1 nm steps of the visible range,
// divided by cieYIntegral().
template <typename Spectrum>
Xyz spectrumToXyz(const Spectrum& spectrum) {
    Xyz xyz{};
    const std::vector<Xyz>& matching = cieMatchingAt1nm();
    for (size_t k = 0; k < matching.size(); ++k) {
        const double v = spectrum(kVisibleLambdaMin + double(k));
        for (int i = 0; i < 3; ++i) xyz[i] += v * matching[k][i];
    }
    const double norm = 1.0 / cieYIntegral();
    return {xyz[0] * norm, xyz[1] * norm, xyz[2] * norm};
}

// Planck's law: a blackbody's spectral radiance at `lambdaNm` and `kelvin`, W / (sr m^2 m).
double planckRadiance(double lambdaNm, double kelvin);

// The colour of a blackbody at `kelvin` with luminance 1 (an emitter whose brightness is given
// separately: pbrt-v4's "blackbody" parameter of lights).
Rgb blackbodyRgb(double kelvin);

// The colour of pbrt-v4's BlackbodySpectrum: Planck's law divided by its value at the peak (Wien's
// displacement law), so its largest spectral value is 1; the emission of a temperature grid.
Rgb blackbodyPeakNormalizedRgb(double kelvin);

// blackbodyPeakNormalizedRgb from a table built once, interpolated linearly in log temperature:
// per-lookup cost for media that emit from a temperature at every collision. 0 at or below 0 K
// (and NaN); the table spans 100 K to 10^6 K, the value at 10^6 K beyond.
Rgb blackbodyPeakNormalizedRgbTabulated(float kelvin);

}  // namespace penumbra
