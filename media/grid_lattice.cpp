#include "media/grid_lattice.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/input_limits.h"

namespace penumbra {

namespace {

std::string describeMatrix(const double m[3][3]) {
    char text[256];
    std::snprintf(text, sizeof text, "[[%g, %g, %g], [%g, %g, %g], [%g, %g, %g]]", m[0][0], m[0][1], m[0][2],
                  m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
    return text;
}

}  // namespace

AxisAlignedMap axisAlignedMap(const std::string& file, const std::string& gridName, const double linear[3][3],
                              const double translation[3]) {
    const std::string grid = "grid \"" + gridName + "\"";
    for (int r = 0; r < 3; ++r) {
        if (!std::isfinite(translation[r]))
            throwFileError(file, grid + "'s transform has a translation that is not finite");
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(linear[r][c]))
                throwFileError(
                    file, grid + "'s transform has a matrix that is not finite: " + describeMatrix(linear));
    }
    AxisAlignedMap map;
    for (int r = 0; r < 3; ++r) {
        const double diagonal = linear[r][r];
        for (int c = 0; c < 3; ++c)
            // Off the diagonal, what rounding leaves of an exact 0 (a rotation by 0 or a multiple of
            // 90 degrees composed in double precision) is taken as 0; anything more rotates or shears.
            if (c != r && !(std::fabs(linear[r][c]) <= 1e-12 * std::fabs(diagonal)))
                throwFileError(file,
                               grid + "'s transform rotates or shears its voxels (index-to-world matrix " +
                                   describeMatrix(linear) +
                                   "); penumbra reads grids whose transform is a scale and a translation");
        if (!(diagonal > 0))
            throwFileError(
                file, grid + "'s transform " + (diagonal < 0 ? "mirrors" : "collapses") +
                          " an axis (index-to-world matrix " + describeMatrix(linear) +
                          "); penumbra reads grids whose transform is a positive scale and a translation");
        map.scale[r] = diagonal;
        map.translation[r] = translation[r];
    }
    return map;
}

int64_t checkLatticeSize(const std::string& file, const std::string& gridName, const VoxelBox& box) {
    const std::string grid = "grid \"" + gridName + "\"";
    int64_t size[3], voxels = 1;
    bool tooMany = false;
    for (int a = 0; a < 3; ++a) {
        // Each side is at most 2^33 (coordinates within 32 bits, and tiles of 4096 beyond them).
        size[a] = box.upper[a] - box.lower[a] + 1;
        if (size[a] > limits::kMaxGridVoxels || voxels > limits::kMaxGridVoxels / size[a]) tooMany = true;
        if (!tooMany) voxels *= size[a];
    }
    if (tooMany) {
        char text[512];
        std::snprintf(
            text, sizeof text,
            "%s's active voxels span %lld x %lld x %lld voxels (index box [%lld, %lld] x [%lld, %lld] x "
            "[%lld, %lld]); penumbra densifies at most %lld voxels (docs/limits.md)",
            grid.c_str(), (long long)size[0], (long long)size[1], (long long)size[2], (long long)box.lower[0],
            (long long)box.upper[0], (long long)box.lower[1], (long long)box.upper[1],
            (long long)box.lower[2], (long long)box.upper[2], (long long)limits::kMaxGridVoxels);
        throwFileError(file, text);
    }
    return voxels;
}

DensityGrid makeLattice(const std::string& file, const std::string& gridName, const VoxelBox& box,
                        const AxisAlignedMap& map, float background) {
    const std::string grid = "grid \"" + gridName + "\"";
    if (!std::isfinite(background))
        throwFileError(file, grid + "'s background value is not finite (" + std::to_string(background) + ")");
    const int64_t voxels = checkLatticeSize(file, gridName, box);
    const int64_t size[3] = {box.upper[0] - box.lower[0] + 1, box.upper[1] - box.lower[1] + 1,
                             box.upper[2] - box.lower[2] + 1};
    DensityGrid out;
    out.nx = int(size[0]);
    out.ny = int(size[1]);
    out.nz = int(size[2]);
    float lower[3], upper[3];
    for (int a = 0; a < 3; ++a) {
        const double lo = map.translation[a] + map.scale[a] * (double(box.lower[a]) - 0.5);
        const double hi = map.translation[a] + map.scale[a] * (double(box.upper[a]) + 0.5);
        if (!(std::fabs(lo) <= double(limits::kMaxCoordinate) &&
              std::fabs(hi) <= double(limits::kMaxCoordinate)))
            throwFileError(
                file, grid + "'s voxels lie beyond 1e18 from the origin in world space (docs/limits.md)");
        lower[a] = float(lo);
        upper[a] = float(hi);
        // lookup() divides by the extent and scales by the cell count: cells less than 8 steps of
        // single precision wide at their distance from the origin would blur into one another.
        const float cell = (upper[a] - lower[a]) / float(size[a]);
        if (!(cell > std::max(std::fabs(lower[a]), std::fabs(upper[a])) * 0x1p-20f) || !(cell > 0))
            throwFileError(file,
                           grid + "'s voxels (" + std::to_string(map.scale[a]) +
                               " wide) are too small for single precision at their distance from the origin");
    }
    out.bounds.lower = Vec3f(lower[0], lower[1], lower[2]);
    out.bounds.upper = Vec3f(upper[0], upper[1], upper[2]);
    out.values.assign(size_t(voxels), background);
    return out;
}

void throwNonFiniteVoxel(const std::string& file, const std::string& gridName, float value, int64_t x,
                         int64_t y, int64_t z) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "grid \"%.100s\" holds a value that is not finite (%g) at voxel (%lld, %lld, %lld)",
                  gridName.c_str(), double(value), (long long)x, (long long)y, (long long)z);
    throwFileError(file, text);
}

}  // namespace penumbra
