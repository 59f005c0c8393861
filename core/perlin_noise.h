// Gradient noise (Perlin, "Improving Noise", SIGGRAPH 2002): pseudo-random gradients on the integer
// lattice, picked by Perlin's permutation of 0..255, blended with the quintic 6t^5 - 15t^4 + 10t^3.
// Values lie in about [-1, 1] and are 0 on the lattice; the pattern repeats every 256 units. The
// same function (permutation, gradients, blend) as pbrt-v4's Noise, so that its procedural media
// and textures look the same here.
#pragma once

#include "core/vec.h"

namespace penumbra {

float perlinNoise(Vec3f p);

// The noise's gradient by forward differences of 0.01 (pbrt-v4's DNoise).
Vec3f perlinNoiseGradient(Vec3f p);

// Fractional Brownian motion: `octaves` octaves of the noise, each at 1.99 times the last one's
// frequency and `omega` times its weight (pbrt-v4's FBm at a footprint finer than every octave).
float fractalNoise(Vec3f p, float omega, int octaves);

// Turbulence: the same sum of |noise|, plus pbrt-v4's 0.2 (about |noise|'s mean) times the weight of
// the octave after the last, which its Turbulence adds at a footprint finer than every octave.
float turbulence(Vec3f p, float omega, int octaves);

}  // namespace penumbra
