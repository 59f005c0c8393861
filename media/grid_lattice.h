// What the OpenVDB and NanoVDB readers share: the lattice a sparse grid's active voxels are
// densified into, and its bounds in world space. Both formats place voxel (i, j, k)'s centre at
// index coordinate (i, j, k); the lattice's cell for it is [i - 0.5, i + 0.5] x ... mapped to world
// space, so that a DensityGrid's cell centres land exactly on the voxel centres.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "media/sampled_grid.h"

namespace penumbra {

// A box of voxels, inclusive at both ends (VDB's CoordBBox).
struct VoxelBox {
    int64_t lower[3] = {0, 0, 0}, upper[3] = {-1, -1, -1};

    bool empty() const { return upper[0] < lower[0] || upper[1] < lower[1] || upper[2] < lower[2]; }
    void add(int64_t x, int64_t y, int64_t z, int64_t size) {
        const int64_t at[3] = {x, y, z};
        const bool first = empty();
        for (int a = 0; a < 3; ++a) {
            lower[a] = first ? at[a] : std::min(lower[a], at[a]);
            upper[a] = first ? at[a] + size - 1 : std::max(upper[a], at[a] + size - 1);
        }
    }
};

// An index-to-world transform that only scales each axis and translates: world = scale * index +
// translation, axis by axis.
struct AxisAlignedMap {
    double scale[3] = {1, 1, 1}, translation[3] = {0, 0, 0};
};

// The map of `linear` (world_r = sum_c linear[r][c] index_c + translation[r]), or an InputError
// naming `file` and the grid when it rotates, shears, mirrors or collapses an axis, or is not finite.
AxisAlignedMap axisAlignedMap(const std::string& file, const std::string& gridName, const double linear[3][3],
                              const double translation[3]);

// The voxels of `box` (not empty); throws InputError when they are more than
// limits::kMaxGridVoxels.
int64_t checkLatticeSize(const std::string& file, const std::string& gridName, const VoxelBox& box);

// A DensityGrid over `box` (not empty) under `map`, every value `background`. Throws InputError when
// the box holds more than limits::kMaxGridVoxels voxels (before allocating anything), when the
// background is not finite, or when the bounds are beyond limits::kMaxCoordinate or their cells too
// small for single precision to tell apart.
DensityGrid makeLattice(const std::string& file, const std::string& gridName, const VoxelBox& box,
                        const AxisAlignedMap& map, float background);

// Where voxel (x, y, z) of `box` is in `grid`'s values (the voxel inside the box).
inline size_t latticeIndex(const DensityGrid& grid, const VoxelBox& box, int64_t x, int64_t y, int64_t z) {
    return grid.indexOf(int(x - box.lower[0]), int(y - box.lower[1]), int(z - box.lower[2]));
}

// "FILE: grid "NAME" holds a value that is not finite (nan) at voxel (i, j, k)": media densities
// must be numbers.
[[noreturn]] void throwNonFiniteVoxel(const std::string& file, const std::string& gridName, float value,
                                      int64_t x, int64_t y, int64_t z);

}  // namespace penumbra
