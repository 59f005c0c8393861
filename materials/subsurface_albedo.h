// The single-scattering albedo of a subsurface material's interior from the diffuse reflectance an
// artist asks for (pbrt-v4's `subsurface` "reflectance" with its mean free path "mfp"), through the
// classical dipole's total diffuse reflectance of a semi-infinite medium under a boundary of
// relative index eta (Jensen, Marschner, Levoy and Hanrahan 2001, "A Practical Model for
// Subsurface Light Transport", eq. 5 and its A; inverted for the albedo as Jensen and Buhler 2002
// do):
//   R_d(a) = a / 2 (1 + exp(-4/3 A sqrt(3 (1 - a)))) exp(-sqrt(3 (1 - a))),
//   A = (1 + F_dr) / (1 - F_dr),
// F_dr the diffuse Fresnel reflectance of the boundary for light inside (computed exactly here,
// where Jensen et al. use a polynomial fit). R_d rises monotonically from 0 at a = 0 to 1 at a = 1,
// so bisection inverts it. pbrt-v4 inverts its photon beam diffusion profile instead; the random
// walk this feeds is exact transport, so neither inversion gives exactly the reflectance asked for
// (docs/subsurface.md measures ours).
#pragma once

#include <cmath>

#include "materials/fresnel.h"

namespace penumbra {

// The dipole's total diffuse reflectance of reduced albedo `albedo` in [0, 1] under a boundary
// whose internal diffuse Fresnel reflectance is `internalReflectance`.
inline double dipoleDiffuseReflectance(double albedo, double internalReflectance) {
    const double a = (1.0 + internalReflectance) / (1.0 - internalReflectance);
    const double root = std::sqrt(3.0 * (1.0 - albedo));
    return albedo / 2.0 * (1.0 + std::exp(-4.0 / 3.0 * a * root)) * std::exp(-root);
}

// The reduced albedo whose dipole reflectance, under a boundary whose internal diffuse Fresnel
// reflectance is `internalReflectance`, is `reflectance` (clamped to [0, 1]): 60 bisection steps,
// exact to double rounding.
inline double albedoForDiffuseReflectanceUnder(double reflectance, double internalReflectance) {
    const double target = std::fmin(std::fmax(reflectance, 0.0), 1.0);
    double low = 0.0, high = 1.0;
    for (int step = 0; step < 60; ++step) {
        const double middle = 0.5 * (low + high);
        (dipoleDiffuseReflectance(middle, internalReflectance) < target ? low : high) = middle;
    }
    return 0.5 * (low + high);
}

// The same under a boundary of relative index eta (inside over outside).
inline double albedoForDiffuseReflectance(double reflectance, double eta) {
    return albedoForDiffuseReflectanceUnder(reflectance, diffuseFresnelReflectance(1.0 / eta));
}

// A medium's absorption and scattering coefficients from a reflectance and its mean free path
// `length` (> 0): sigma_t = 1 / length, of which the albedo above scatters; scattering is the
// reduced coefficient's, sigma_s = sigma_s' / (1 - g), so that the asymmetry g keeps the
// reflectance.
struct SubsurfaceCoefficients {
    double sigmaA, sigmaS;
};
inline SubsurfaceCoefficients coefficientsForDiffuseReflectance(double reflectance, double length,
                                                                double internalReflectance, double g) {
    const double albedo = albedoForDiffuseReflectanceUnder(reflectance, internalReflectance);
    return {(1.0 - albedo) / length, albedo / (length * (1.0 - g))};
}

}  // namespace penumbra
