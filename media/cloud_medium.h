// A procedural cloud (pbrt-v4's `cloud` medium, the one its clouds scene uses): a density made of
// Perlin noise (core/perlin_noise.h) in the box `bounds` of the medium's space, times sigma_a and
// sigma_s. Five octaves of noise at `frequency`, their lookup point first displaced twice along the
// noise's gradient (`wispiness`: 0 for none), thinning with height y and scaled by `density`,
// clamped to [0, 1], plus a base that fills the box below y = 0.5 (pbrt-v4's CloudMedium::Density,
// the same constants). The density never exceeds 1, so sigma_t is the majorant throughout the box.
#pragma once

#include <algorithm>

#include "core/henyey_greenstein.h"
#include "core/perlin_noise.h"
#include "core/rgb.h"
#include "core/transform.h"
#include "media/majorant_grid.h"
#include "media/sampled_grid.h"

namespace penumbra {

struct CloudMedium {
    GridBounds bounds;
    Rgb sigmaA{1.0f}, sigmaS{1.0f};
    HenyeyGreenstein phase;
    float density = 1.0f, wispiness = 1.0f, frequency = 5.0f;
    Transform toWorld;  // medium space to world
    MajorantGrid majorants;

    void buildMajorants() {
        const Rgb sigmaT = sigmaA + sigmaS;
        majorants.build(bounds, [&](Vec3f, Vec3f) { return sigmaT; });
    }

    float densityAt(Vec3f p) const {
        Vec3f q = p * frequency;
        if (wispiness > 0.0f) {
            float amplitude = 0.05f * wispiness, scale = 10.0f;
            for (int i = 0; i < 2; ++i) {
                q = q + perlinNoiseGradient(q * scale) * amplitude;
                amplitude *= 0.5f;
                scale *= 1.99f;
            }
        }
        float d = 0.0f, amplitude = 0.5f, scale = 1.0f;
        for (int i = 0; i < 5; ++i) {
            d += amplitude * perlinNoise(q * scale);
            amplitude *= 0.5f;
            scale *= 1.99f;
        }
        d = std::clamp((1.0f - p.y) * 4.5f * density * d, 0.0f, 1.0f);
        d += 2.0f * std::max(0.0f, 0.5f - p.y);
        return std::clamp(d, 0.0f, 1.0f);
    }
};

}  // namespace penumbra
