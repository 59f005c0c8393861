// Heterogeneous media's grids from OpenVDB files (.vdb), through the OpenVDB library (Debian's
// libopenvdb-dev, OpenVDB 10), which the volume plugin holds (media/volume_plugin.h): it is loaded
// the first time a .vdb file is read (its headers stay in openvdb_library_reader.cpp).
//
// A float grid's active voxels (and active tiles) are densified into the box that holds them;
// inactive voxels in it read as the grid's background value. The grid's transform must be linear
// and axis-aligned, a positive scale and a translation (uniform or not); rotated, sheared and
// frustum transforms are refused. Voxel (i, j, k)'s centre is at index coordinate (i, j, k): the
// DensityGrid's cell centres land on the voxel centres in world space.
//
// The file is checked to be a regular file within limits::kMaxVolumeFileBytes, and the grid's
// bounding box in its meta data (OpenVDB writes it) against limits::kMaxGridVoxels before its tree is
// read. OpenVDB's own reader is not hardened against hostile files (docs/limits.md).
#pragma once

#include <filesystem>
#include <string>

#include "media/sampled_grid.h"

namespace penumbra {

// The float grid named `gridName` of the OpenVDB file `file`. Throws InputError naming the file on
// any bad input: not a regular file, not an OpenVDB file, no such grid (the message lists those the
// file holds), another type than float, a transform that is not a scale and a translation, no
// active voxels, too many, values that are not finite.
// A plugin that cannot be loaded is an InputError naming the plugin's file.
DensityGrid readOpenVdbGrid(const std::filesystem::path& file, const std::string& gridName);

}  // namespace penumbra
