// Sampling a point of [0, 1)^2 with a density proportional to a piecewise-constant function given
// on a grid of cells (an environment map's luminance times sin(theta)): a marginal distribution
// over rows, then a conditional one over the chosen row's columns (pbrt-v4's
// PiecewiseConstant2D, Mitsuba's Hierarchical2D in its simplest form). Continuous: the sample
// lies anywhere inside its cell, so pdf() is a density over [0, 1)^2, not a cell probability.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/vec.h"

namespace penumbra {

// One row: values f_0..f_{n-1} over [0, 1), each cell 1/n wide.
class PiecewiseConstant1D {
public:
    PiecewiseConstant1D() = default;
    // Negative or non-finite values count as 0.
    explicit PiecewiseConstant1D(const float* values, size_t n) : function_(n), cdf_(n + 1) {
        double total = 0.0;
        cdf_[0] = 0.0;
        for (size_t i = 0; i < n; ++i) {
            const float f = values[i];
            function_[i] = (f > 0.0f && std::isfinite(f)) ? f : 0.0f;
            total += function_[i];
            cdf_[i + 1] = total;
        }
        integral_ = total / double(n);
        if (total > 0.0)
            for (double& c : cdf_) c /= total;
        else  // all zero: uniform, so that sample() still returns a point (of density 0 in the 2D sense)
            for (size_t i = 0; i <= n; ++i) cdf_[i] = double(i) / double(n);
        cdf_[n] = 1.0;
    }

    size_t size() const { return function_.size(); }
    // The mean of the function over [0, 1).
    double integral() const { return integral_; }
    float value(size_t i) const { return function_[i]; }

    // A point x in [0, 1) with density value(cell) / integral(); `cell` receives its cell.
    float sample(float u, size_t& cell) const {
        // The last cdf entry <= u, skipping cells of zero width.
        const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u));
        size_t i = size_t(std::clamp<ptrdiff_t>(it - cdf_.begin() - 1, 0, ptrdiff_t(size()) - 1));
        while (cdf_[i + 1] <= cdf_[i] && i > 0) --i;  // a zero-width cell reached through rounding
        cell = i;
        const double width = cdf_[i + 1] - cdf_[i];
        const double offset = width > 0.0 ? (double(u) - cdf_[i]) / width : 0.5;
        const float x = float((double(i) + std::clamp(offset, 0.0, 1.0)) / double(size()));
        return std::min(x, 1.0f - 0x1p-24f);
    }
    // The density of x (in [0, 1)).
    float pdf(float x) const {
        if (!(integral_ > 0.0)) return 0.0f;
        const size_t i = std::min(size_t(std::max(x, 0.0f) * float(size())), size() - 1);
        return float(function_[i] / integral_);
    }

private:
    std::vector<float> function_;
    std::vector<double> cdf_;
    double integral_ = 0.0;
};

// A width x height grid, row-major (row v, column u); (0, 0) is the first value.
class PiecewiseConstant2D {
public:
    PiecewiseConstant2D() = default;
    PiecewiseConstant2D(const std::vector<float>& values, size_t width, size_t height)
        : width_(width), height_(height) {
        std::vector<float> rowIntegrals(height);
        rows_.reserve(height);
        for (size_t v = 0; v < height; ++v) {
            rows_.emplace_back(&values[v * width], width);
            rowIntegrals[v] = float(rows_.back().integral());
        }
        marginal_ = PiecewiseConstant1D(rowIntegrals.data(), height);
    }

    bool empty() const { return !(marginal_.integral() > 0.0); }
    // The mean of the function over [0, 1)^2.
    double integral() const { return marginal_.integral(); }

    // A point (u along a row, v across rows) with density pdf().
    Vec2f sample(Vec2f u, float* density = nullptr) const {
        size_t row = 0, column = 0;
        const float v = marginal_.sample(u.y, row);
        const float x = rows_[row].sample(u.x, column);
        if (density) *density = empty() ? 0.0f : float(double(rows_[row].value(column)) / integral());
        return {x, v};
    }
    float pdf(Vec2f p) const {
        if (empty()) return 0.0f;
        const size_t row = std::min(size_t(std::max(p.y, 0.0f) * float(height_)), height_ - 1);
        const size_t column = std::min(size_t(std::max(p.x, 0.0f) * float(width_)), width_ - 1);
        return float(double(rows_[row].value(column)) / integral());
    }

private:
    size_t width_ = 0, height_ = 0;
    std::vector<PiecewiseConstant1D> rows_;
    PiecewiseConstant1D marginal_;
};

}  // namespace penumbra
