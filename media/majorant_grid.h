// Majorants of a heterogeneous medium: a coarse grid over the medium's box holding, per cell, the
// largest sigma_t (per channel) anywhere in the cell (pbrt-v4 uses 16^3), so that free-flight
// sampling makes few null collisions where the medium is thin and none outside it. A ray walks the
// coarse cells it crosses (Amanatides and Woo's DDA), each a segment with a constant majorant.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/rgb.h"
#include "core/vec.h"
#include "media/sampled_grid.h"

namespace penumbra {

struct MajorantGrid {
    static constexpr int kResolution = 16;

    GridBounds bounds;
    std::vector<Rgb> sigmaMaj;  // kResolution^3, x fastest

    // Fills the grid over `box`, each cell's majorant cellMajorant(lower, upper) of the cell's corners.
    template <typename CellMajorant>
    void build(const GridBounds& box, CellMajorant&& cellMajorant) {
        constexpr int n = kResolution;
        bounds = box;
        sigmaMaj.assign(size_t(n) * n * n, Rgb(0.0f));
        const Vec3f lower = box.lower, extent = box.upper - box.lower;
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const Vec3f a =
                        lower + scaleComponents(extent, Vec3f(float(x) / n, float(y) / n, float(z) / n));
                    const Vec3f b = lower + scaleComponents(extent, Vec3f(float(x + 1) / n, float(y + 1) / n,
                                                                          float(z + 1) / n));
                    sigmaMaj[(size_t(z) * n + size_t(y)) * n + size_t(x)] = cellMajorant(a, b);
                }
    }
};

// The segments of constant majorant along a ray through a majorant grid.
class GridMajorantWalk {
public:
    struct Segment {
        float tMin, tMax;
        Rgb sigmaMaj;
    };

    // The ray origin + t * direction (the grid's space; t in the caller's units) over [tMin, tMax).
    GridMajorantWalk(const MajorantGrid& grid, Vec3f origin, Vec3f direction, float tMin, float tMax)
        : sigmaMaj_(&grid.sigmaMaj) {
        constexpr int n = MajorantGrid::kResolution;
        const GridBounds& box = grid.bounds;
        const Vec3f extent = box.upper - box.lower;
        // In coarse-cell units: the grid spans [0, n)^3.
        const Vec3f o = scaleComponents(origin - box.lower, Vec3f(n / extent.x, n / extent.y, n / extent.z));
        const Vec3f d = scaleComponents(direction, Vec3f(n / extent.x, n / extent.y, n / extent.z));
        // Clip to the grid's box.
        for (int axis = 0; axis < 3; ++axis) {
            if (d[axis] == 0.0f) {
                if (o[axis] < 0.0f || o[axis] > float(n)) tMin = tMax;
                continue;
            }
            float t0 = (0.0f - o[axis]) / d[axis], t1 = (float(n) - o[axis]) / d[axis];
            if (t0 > t1) std::swap(t0, t1);
            tMin = std::max(tMin, t0);
            tMax = std::min(tMax, t1);
        }
        tMin_ = tMin;
        tMax_ = tMax;
        if (!(tMin < tMax)) return;
        const Vec3f start = o + d * tMin;
        for (int axis = 0; axis < 3; ++axis) {
            cell_[axis] = std::clamp(int(std::floor(start[axis])), 0, n - 1);
            if (d[axis] == 0.0f) {
                nextCrossing_[axis] = std::numeric_limits<float>::infinity();
                step_[axis] = 0;
                delta_[axis] = 0.0f;
            } else if (d[axis] > 0.0f) {
                nextCrossing_[axis] = tMin + (float(cell_[axis] + 1) - start[axis]) / d[axis];
                step_[axis] = 1;
                delta_[axis] = 1.0f / d[axis];
            } else {
                nextCrossing_[axis] = tMin + (float(cell_[axis]) - start[axis]) / d[axis];
                step_[axis] = -1;
                delta_[axis] = -1.0f / d[axis];
            }
        }
    }

    // The next segment, false when the ray has left the grid or reached tMax.
    bool next(Segment& segment) {
        if (!(tMin_ < tMax_)) return false;
        constexpr int n = MajorantGrid::kResolution;
        int axis = nextCrossing_[0] < nextCrossing_[1] ? 0 : 1;
        if (nextCrossing_[2] < nextCrossing_[axis]) axis = 2;
        const float end = std::min(tMax_, nextCrossing_[axis]);
        segment = {tMin_, end,
                   (*sigmaMaj_)[(size_t(cell_[2]) * n + size_t(cell_[1])) * n + size_t(cell_[0])]};
        tMin_ = end;
        cell_[axis] += step_[axis];
        nextCrossing_[axis] += delta_[axis];
        if (cell_[axis] < 0 || cell_[axis] >= n) tMin_ = tMax_;
        return true;
    }

private:
    const std::vector<Rgb>* sigmaMaj_;
    float tMin_ = 0.0f, tMax_ = 0.0f;
    int cell_[3] = {0, 0, 0}, step_[3] = {0, 0, 0};
    float nextCrossing_[3] = {0.0f, 0.0f, 0.0f}, delta_[3] = {0.0f, 0.0f, 0.0f};
};

}  // namespace penumbra
