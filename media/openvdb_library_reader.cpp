#include "media/openvdb_library_reader.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <exception>

#include "core/error.h"
#include "core/input_limits.h"
#include "media/grid_lattice.h"

namespace penumbra {

namespace {

std::string quotedName(const std::string& name) {
    return "\"" + (name.size() > 64 ? name.substr(0, 64) + "..." : name) + "\"";
}

// The grid's bounding box as OpenVDB wrote it in its meta data (io::File::write adds it), if any.
bool metadataBox(const openvdb::GridBase& grid, VoxelBox& box) {
    const auto lower = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
    const auto upper = grid.getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
    if (!lower || !upper) return false;
    for (int a = 0; a < 3; ++a) {
        box.lower[a] = lower->value()[a];
        box.upper[a] = upper->value()[a];
    }
    return !box.empty();
}

DensityGrid densify(const openvdb::FloatGrid& grid, const std::string& file, const std::string& gridName) {
    const openvdb::math::Transform& transform = grid.transform();
    if (!transform.isLinear())
        throwFileError(file,
                       "OpenVDB grid " + quotedName(gridName) + " has a " + transform.mapType() +
                           " transform, which is not linear; penumbra reads grids whose transform is a scale "
                           "and a translation");
    // OpenVDB multiplies row vectors: world = index * M, the translation in M's last row.
    const openvdb::math::Mat4d m = transform.baseMap()->getAffineMap()->getMat4();
    double linear[3][3], translation[3];
    for (int r = 0; r < 3; ++r) {
        translation[r] = m(3, r);
        for (int c = 0; c < 3; ++c) linear[r][c] = m(c, r);
    }
    const AxisAlignedMap map = axisAlignedMap(file, gridName, linear, translation);

    const openvdb::CoordBBox active = grid.evalActiveVoxelBoundingBox();
    if (active.empty())
        throwFileError(file, "OpenVDB grid " + quotedName(gridName) + " has no active voxels");
    VoxelBox box;
    for (int a = 0; a < 3; ++a) {
        box.lower[a] = active.min()[a];
        box.upper[a] = active.max()[a];
    }
    DensityGrid out = makeLattice(file, gridName, box, map, grid.background());
    for (auto value = grid.cbeginValueOn(); value; ++value) {
        const float v = *value;
        const openvdb::CoordBBox voxels = value.getBoundingBox();
        if (!std::isfinite(v))
            throwNonFiniteVoxel(file, gridName, v, voxels.min().x(), voxels.min().y(), voxels.min().z());
        for (int64_t z = voxels.min().z(); z <= voxels.max().z(); ++z)
            for (int64_t y = voxels.min().y(); y <= voxels.max().y(); ++y) {
                const size_t row = latticeIndex(out, box, voxels.min().x(), y, z);
                std::fill(out.values.begin() + ptrdiff_t(row),
                          out.values.begin() + ptrdiff_t(row) + (voxels.max().x() - voxels.min().x() + 1), v);
            }
    }
    return out;
}

}  // namespace

DensityGrid readOpenVdbGridWithLibrary(const std::string& file, const std::string& gridName) {
    static const bool initialized = [] {
        openvdb::initialize();
        return true;
    }();
    (void)initialized;
    try {
        openvdb::io::File vdb(file);
        // Without delayed loading: the tree is read now, not through a memory map of a file that
        // may change under it.
        vdb.open(/*delayLoad=*/false);
        const openvdb::GridPtrVecPtr grids = vdb.readAllGridMetadata();
        openvdb::GridBase::ConstPtr meta;
        std::string names;
        int listed = 0;
        for (const openvdb::GridBase::Ptr& grid : *grids) {
            if (!meta && grid->getName() == gridName) meta = grid;
            if (listed < 16)
                names += (listed ? ", " : "") + quotedName(grid->getName()) + " (" + grid->valueType() + ")";
            ++listed;
        }
        if (listed > 16) names += " and " + std::to_string(listed - 16) + " more";
        if (!meta)
            throwFileError(file, "has no OpenVDB grid named " + quotedName(gridName) +
                                     "; its grids: " + (names.empty() ? std::string("none") : names));
        if (!meta->isType<openvdb::FloatGrid>())
            throwFileError(file, "OpenVDB grid " + quotedName(gridName) + " holds values of type " +
                                     meta->valueType() + "; penumbra reads grids of type float");
        VoxelBox box;
        // Too many voxels are refused from the meta data, before the tree is read.
        if (metadataBox(*meta, box)) checkLatticeSize(file, gridName, box);
        const auto grid = openvdb::gridConstPtrCast<openvdb::FloatGrid>(vdb.readGrid(gridName));
        vdb.close();
        if (!grid)
            throwFileError(file,
                           "OpenVDB grid " + quotedName(gridName) + " could not be read as a float grid");
        return densify(*grid, file, gridName);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        // openvdb::Exception and what the library lets through (std::bad_alloc of a huge count).
        throwFileError(file, std::string("cannot read the OpenVDB file: ") + e.what());
    }
}

}  // namespace penumbra
