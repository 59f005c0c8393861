// A medium whose coefficients vary in colour and in space (pbrt-v4's `rgbgrid`): sigma_a(p) and
// sigma_s(p) each an RGB lattice (media/sampled_grid.h) over the same box, times `scale`, and
// emitted radiance Le(p) an RGB lattice times `emissionScale` (the medium emitting sigma_a * Le per
// unit length). Each of the three may instead be the same everywhere in the box (pbrt-v4 takes a
// missing sigma_a or sigma_s as 1); there is nothing outside the box.
#pragma once

#include <optional>

#include "core/henyey_greenstein.h"
#include "core/rgb.h"
#include "core/transform.h"
#include "media/majorant_grid.h"
#include "media/sampled_grid.h"

namespace penumbra {

struct RgbGridMedium {
    GridBounds bounds;
    std::optional<RgbGrid> sigmaA, sigmaS, emission;                      // lattices over `bounds`
    Rgb uniformSigmaA{0.0f}, uniformSigmaS{0.0f}, uniformEmission{0.0f};  // where there is no lattice
    float scale = 1.0f, emissionScale = 1.0f;
    HenyeyGreenstein phase;
    Transform toWorld;  // medium space to world
    MajorantGrid majorants;

    // Fills the majorants from the coefficients: to be called once they are set.
    void buildMajorants() {
        majorants.build(bounds, [&](Vec3f a, Vec3f b) {
            const Rgb maxA = sigmaA ? sigmaA->maxOver(a, b) : uniformSigmaA;
            const Rgb maxS = sigmaS ? sigmaS->maxOver(a, b) : uniformSigmaS;
            return (maxA + maxS) * scale;
        });
    }
    bool inside(Vec3f p) const {
        return p.x >= bounds.lower.x && p.y >= bounds.lower.y && p.z >= bounds.lower.z &&
               p.x <= bounds.upper.x && p.y <= bounds.upper.y && p.z <= bounds.upper.z;
    }
    Rgb sigmaAAt(Vec3f p) const { return valueAt(sigmaA, uniformSigmaA, p) * scale; }
    Rgb sigmaSAt(Vec3f p) const { return valueAt(sigmaS, uniformSigmaS, p) * scale; }
    Rgb emissionAt(Vec3f p) const { return valueAt(emission, uniformEmission, p) * emissionScale; }

private:
    Rgb valueAt(const std::optional<RgbGrid>& lattice, Rgb uniform, Vec3f p) const {
        if (lattice) return lattice->lookup(p);
        return inside(p) ? uniform : Rgb(0.0f);
    }
};

}  // namespace penumbra
