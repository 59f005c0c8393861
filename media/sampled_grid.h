// A field sampled on a regular lattice, as heterogeneous media store density, temperature, emission
// scale (DensityGrid: one float per cell) or RGB coefficients (RgbGrid). pbrt-v4's SampledGrid
// convention: `bounds` split into nx * ny * nz cells, the value of cell (x, y, z) at its centre,
// trilinear in between, blending with 0 beyond the outermost centres (a point within half a cell of
// the bounds' faces), and 0 outside the bounds.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/check.h"
#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

struct GridBounds {
    Vec3f lower{0.0f, 0.0f, 0.0f}, upper{1.0f, 1.0f, 1.0f};
};

inline float componentMax(float a, float b) { return std::max(a, b); }
inline Rgb componentMax(Rgb a, Rgb b) { return {std::max(a.r, b.r), std::max(a.g, b.g), std::max(a.b, b.b)}; }

template <typename Value>
struct SampledGrid {
    int nx = 0, ny = 0, nz = 0;
    GridBounds bounds;
    std::vector<Value> values;  // x fastest: values[(z * ny + y) * nx + x]

    size_t indexOf(int x, int y, int z) const {
        return (size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x);
    }
    // The lattice value, 0 outside it.
    Value at(int x, int y, int z) const {
        if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return Value(0.0f);
        return values[indexOf(x, y, z)];
    }
    // The field at `p` (in the grid's space): trilinear between the cell centres.
    Value lookup(Vec3f p) const {
        PENUMBRA_CHECK(values.size() == size_t(nx) * size_t(ny) * size_t(nz),
                       "a grid holds nx * ny * nz values");
        const Vec3f extent = bounds.upper - bounds.lower;
        const float gx = (p.x - bounds.lower.x) / extent.x * float(nx) - 0.5f;
        const float gy = (p.y - bounds.lower.y) / extent.y * float(ny) - 0.5f;
        const float gz = (p.z - bounds.lower.z) / extent.z * float(nz) - 0.5f;
        // Nothing outside the bounds (the majorant walk covers them alone), NaN included.
        if (!(gx >= -0.5f && gy >= -0.5f && gz >= -0.5f && gx <= float(nx) - 0.5f && gy <= float(ny) - 0.5f &&
              gz <= float(nz) - 0.5f))
            return Value(0.0f);
        const int x = int(std::floor(gx)), y = int(std::floor(gy)), z = int(std::floor(gz));
        const float fx = gx - float(x), fy = gy - float(y), fz = gz - float(z);
        auto lerp = [](float t, Value a, Value b) { return a + t * (b - a); };
        const Value c00 = lerp(fx, at(x, y, z), at(x + 1, y, z));
        const Value c10 = lerp(fx, at(x, y + 1, z), at(x + 1, y + 1, z));
        const Value c01 = lerp(fx, at(x, y, z + 1), at(x + 1, y, z + 1));
        const Value c11 = lerp(fx, at(x, y + 1, z + 1), at(x + 1, y + 1, z + 1));
        return lerp(fz, lerp(fy, c00, c10), lerp(fy, c01, c11));
    }
    // The largest value lookup() can return within the box [lower, upper] (grid space), per channel:
    // the maximum over the lattice values whose cells' centres are within one cell of it.
    Value maxOver(Vec3f lower, Vec3f upper) const {
        const Vec3f extent = bounds.upper - bounds.lower;
        auto range = [](float a, float b, float origin, float size, int n, int& first, int& last) {
            first = std::clamp(int(std::floor((a - origin) / size * float(n) - 0.5f)), 0, n - 1);
            last = std::clamp(int(std::floor((b - origin) / size * float(n) - 0.5f)) + 1, 0, n - 1);
        };
        int x0, x1, y0, y1, z0, z1;
        range(lower.x, upper.x, bounds.lower.x, extent.x, nx, x0, x1);
        range(lower.y, upper.y, bounds.lower.y, extent.y, ny, y0, y1);
        range(lower.z, upper.z, bounds.lower.z, extent.z, nz, z0, z1);
        Value m(0.0f);
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) m = componentMax(m, values[indexOf(x, y, z)]);
        return m;
    }
};

using DensityGrid = SampledGrid<float>;
using RgbGrid = SampledGrid<Rgb>;

}  // namespace penumbra
