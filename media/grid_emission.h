// What a grid medium emits (pbrt-v4's GridMedium and NanoVDBMedium): radiance Le(p), the medium
// emitting sigma_a(p) * Le(p) per unit length. Le(p) = scale(p) times either a blackbody at the
// temperature (T(p) - temperatureOffset) * temperatureScale (pbrt-v4's BlackbodySpectrum,
// normalized to a largest spectral value of 1; none at or below 100 K, as in pbrt-v4) when there is
// a temperature grid, or a constant radiance. scale(p) is a number, or a grid of its own (pbrt-v4's
// "Lescale" of uniformgrid), times the number.
#pragma once

#include <optional>

#include "core/colorimetry.h"
#include "core/rgb.h"
#include "media/sampled_grid.h"

namespace penumbra {

struct GridEmission {
    Rgb radiance{0.0f};                      // Le where there is no temperature grid
    std::optional<DensityGrid> temperature;  // kelvin, in the medium's space
    float temperatureOffset = 0.0f, temperatureScale = 1.0f;
    std::optional<DensityGrid> scaleGrid;  // in the medium's space
    float scale = 1.0f;

    bool emits() const { return scale > 0.0f && (temperature || !radiance.isBlack()); }

    Rgb at(Vec3f pMedium) const {
        const float s = scaleGrid ? scale * scaleGrid->lookup(pMedium) : scale;
        if (!(s > 0.0f)) return Rgb(0.0f);
        if (!temperature) return radiance * s;
        const float kelvin = (temperature->lookup(pMedium) - temperatureOffset) * temperatureScale;
        if (!(kelvin > 100.0f)) return Rgb(0.0f);
        return blackbodyPeakNormalizedRgbTabulated(kelvin) * s;
    }
};

}  // namespace penumbra
