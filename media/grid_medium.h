// A medium whose density varies in space, on a lattice (pbrt-v4's `uniformgrid`, OpenVDB and
// NanoVDB grids): sigma_a(p) = sigmaA * d(p) and sigma_s(p) = sigmaS * d(p), d trilinear on the
// grid (media/sampled_grid.h), 0 outside it, and what it emits (media/grid_emission.h). The grids
// live in the medium's own space, placed in the world by `toWorld`; distances along a ray, and so
// the coefficients, are in world units.
#pragma once

#include "core/henyey_greenstein.h"
#include "core/rgb.h"
#include "core/transform.h"
#include "media/grid_emission.h"
#include "media/majorant_grid.h"
#include "media/sampled_grid.h"

namespace penumbra {

struct GridMedium {
    DensityGrid density;
    Rgb sigmaA{0.0f}, sigmaS{1.0f};  // per unit density (pbrt-v4's `scale` folded in)
    HenyeyGreenstein phase;
    GridEmission emission;
    Transform toWorld;  // medium space to world
    MajorantGrid majorants;

    // Fills the majorants from the density: to be called once the grid and coefficients are set.
    void buildMajorants() {
        const Rgb sigmaT = sigmaA + sigmaS;
        majorants.build(density.bounds, [&](Vec3f a, Vec3f b) { return sigmaT * density.maxOver(a, b); });
    }
    float densityAt(Vec3f pMedium) const { return density.lookup(pMedium); }
};

}  // namespace penumbra
