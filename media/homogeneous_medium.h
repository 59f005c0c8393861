// A medium with the same coefficients everywhere (fog, an absorbing liquid): absorption sigma_a
// and scattering sigma_s per unit length, a Henyey-Greenstein phase function, and emitted radiance
// Le (emission per unit length is sigma_a * Le, as in pbrt-v4). Its majorant is sigma_t itself, so
// delta tracking through it makes no null collisions.
#pragma once

#include "core/henyey_greenstein.h"
#include "core/rgb.h"

namespace penumbra {

struct HomogeneousMedium {
    Rgb sigmaA{0.0f}, sigmaS{0.0f};
    Rgb emission{0.0f};  // Le
    HenyeyGreenstein phase;
};

}  // namespace penumbra
