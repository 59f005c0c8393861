// pbrt-v4 spectra as RGB. penumbra renders in linear Rec.709 (sRGB primaries) RGB, so every
// spectrum a pbrt scene gives is turned into an RGB triple once, by one stated method:
//  - "rgb" values pass through: pbrt-v4 makes lights' RGB values RGBIlluminantSpectrum (the RGB
//    times the colour space's illuminant, D65 for sRGB) and divides by that illuminant's
//    luminance, which nets out to the RGB value on an sRGB film; reflectances are the RGB.
//  - "blackbody" T: Planck's law at T kelvin seen through the CIE 1931 colour matching functions
//    (core/colorimetry.h), normalized to luminance Y = 1 (blackbodyRgb): pbrt-v4 normalizes an
//    emitter's spectrum to 1 nit before applying its "scale" / "power".
//  - (wavelength, value) pairs: piecewise linear. As an emitter, like a blackbody (Y = 1). As a
//    reflectance or an index of refraction, the spectrum seen under a 6504 K blackbody (close to
//    D65) divided per channel by that illuminant's own RGB, so a constant spectrum c gives c.
//  - named spectra: the metals' complex indices ("metal-Cu-eta", "metal-Au-k", ... for Cu, Au,
//    Ag, Al) as the RGB values Tungsten and Mitsuba use (at about 650, 550 and 450 nm), the
//    glasses' ("glass-BK7", ...) index at the helium d line (587.6 nm, n_d of Schott's data
//    sheets; pbrt-v4's "glass-F5", "glass-F10" and "glass-F11" are Schott's SF5, SF10 and SF11),
//    "stdillum-D65" as white and "stdillum-A" as a 2856 K blackbody.
//  - a spectrum file (pbrt-v4's .spd: a spectrum parameter's string that names no named spectrum):
//    its (wavelength, value) pairs, read by the parser (parseSpectrumFile) and then as above.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "core/colorimetry.h"
#include "core/rgb.h"

namespace penumbra::pbrt {

// (wavelength in nm, value) pairs, sorted by wavelength.
Rgb emissionSpectrumRgb(const std::vector<double>& pairs);
Rgb reflectanceSpectrumRgb(const std::vector<double>& pairs);

// A named spectrum of pbrt-v4 as RGB; empty for names penumbra does not know.
std::optional<Rgb> namedSpectrumRgb(std::string_view name);

// The (wavelength, value) pairs of a spectrum file: numbers separated by white space, '#' to the
// end of a line a comment, wavelengths increasing, every number finite, at least one pair. Throws
// InputError at `fileName`:LINE otherwise.
std::vector<double> parseSpectrumFile(std::string_view text, const std::string& fileName);

}  // namespace penumbra::pbrt
