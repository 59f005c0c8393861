// Functions on the unit square given at the nodes of a regular grid, bilinear between them, and
// depending on up to three parameters given at nodes of their own, linear between those: the tables
// of a measured BRDF (materials/measured_bsdf.h), after Dupuy and Jakob 2018, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering", whose data are such tables.
//
// - ParameterGrid: where the parameters' nodes are; blend() gives, for parameter values, the (at most
//   eight) slices of a table around them and their weights.
// - BilinearTable: values (one or more channels) interpolated in the square and across slices.
// - PiecewiseLinear2D: a density on the square, sampled by inversion (a marginal density over rows,
//   then the chosen height's density along x; both are linear ramps within a cell, inverted exactly),
//   with the inverse of that warp. Blending the slices' densities blends their cumulative integrals
//   the same way, so a blended density is sampled exactly as well.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/vec.h"

namespace penumbra {

// The slices of a table near some parameter values and their weights (summing to 1).
struct ParameterBlend {
    std::array<uint32_t, 8> slice{};
    std::array<float, 8> weight{};
    int count = 1;  // a table without parameters has the one slice 0 with weight 1

    ParameterBlend() { weight[0] = 1.0f; }
};

// The nodes of each parameter (strictly increasing, the reader checks), the last one varying
// fastest between slices.
class ParameterGrid {
public:
    ParameterGrid() = default;
    explicit ParameterGrid(std::vector<std::vector<float>> nodes);

    size_t parameterCount() const { return nodes_.size(); }
    size_t sliceCount() const { return slices_; }
    // Values outside a parameter's nodes take its first or last node (NaN the first).
    ParameterBlend blend(const float* values) const;

private:
    std::vector<std::vector<float>> nodes_;
    std::vector<uint32_t> strides_;
    size_t slices_ = 1;
};

// values[slice][y][x][channel], x and y on nodes 0, 1/(nx-1), ..., 1.
class BilinearTable {
public:
    BilinearTable() = default;
    BilinearTable(std::vector<float> values, int nx, int ny, int channels);

    int nx() const { return nx_; }
    int ny() const { return ny_; }
    // Channel `channel` at p (clamped to the square).
    float eval(Vec2f p, const ParameterBlend& blend, int channel = 0) const;
    // Channels 0 to 2 at p.
    std::array<float, 3> eval3(Vec2f p, const ParameterBlend& blend) const;

private:
    std::vector<float> values_;
    int nx_ = 2, ny_ = 2, channels_ = 1;
};

class PiecewiseLinear2D {
public:
    struct Warped {
        Vec2f point;
        float pdf = 0.0f;
    };

    PiecewiseLinear2D() = default;
    // values[slice][y][x], each slice at least 0 and with a positive integral (scaled to 1 here).
    PiecewiseLinear2D(const std::vector<float>& values, int nx, int ny, size_t slices);

    // The point of the square that u (in [0, 1)^2) maps to, and the density there.
    Warped sample(Vec2f u, const ParameterBlend& blend) const;
    // The u that sample() maps to p, and the density at p.
    Warped invert(Vec2f p, const ParameterBlend& blend) const;
    float pdf(Vec2f p, const ParameterBlend& blend) const;

private:
    float density(size_t node, const ParameterBlend& blend) const;
    float rowCumulative(size_t node, const ParameterBlend& blend) const;
    float marginal(size_t row, const ParameterBlend& blend) const;

    int nx_ = 2, ny_ = 2;
    std::vector<float> density_;        // [slice][y][x], integrating to 1 over the square
    std::vector<float> rowCumulative_;  // [slice][y][x]: integral of the density along row y up to x
    std::vector<float> marginal_;       // [slice][y]: integral over the square below row y
};

}  // namespace penumbra
