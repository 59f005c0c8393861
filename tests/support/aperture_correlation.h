// How much an out-of-focus blur on the film looks like an aperture's image: the Pearson
// correlation of the film's green channel with the aperture's transmission (or its mirror image,
// left to right) on a 24 x 24 grid over the image's square [-1, 1]^2, placed on the film with its
// centre at (cx, cy) and `scale` pixels per unit, +y up. Each grid cell takes the mean of the 3 x 3
// pixels around it, so that the noise of a single pixel matters less.
#pragma once

#include <cmath>

#include "cameras/aperture.h"
#include "film/film.h"

namespace penumbra::testing {

inline double apertureCorrelation(const Film& film, const Aperture& aperture, double cx, double cy,
                                  double scale, bool mirrored) {
    constexpr int kGrid = 24;
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const float u = -1.0f + 2.0f * (i + 0.5f) / kGrid, v = 1.0f - 2.0f * (j + 0.5f) / kGrid;
            const int x = int(cx + u * scale), y = int(cy - v * scale);
            double a = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) a += film.at(x + dx, y + dy).mean().g / 9.0;
            const double b = aperture.transmission({mirrored ? -u : u, v});
            sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
        }
    const double n = kGrid * kGrid;
    return (sab - sa * sb / n) / std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n));
}

}  // namespace penumbra::testing
