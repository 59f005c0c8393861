// Heterogeneous media's grids from NanoVDB files (.nvdb), the files pbrt-v4's "nanovdb" medium
// reads ("density", "temperature"). A reader of the documented binary layout (NanoVDB.h and
// util/IO.h of OpenVDB's nanovdb/), no NanoVDB library: Debian has none.
//
// Accepted: files with the magic number "NanoVDB0" of NanoVDB 32.3 (the version pbrt-v4 vendors,
// 32.3.3) and 32.4 (OpenVDB 10.x), whose layout of float grids is the same; segments of any number of
// grids, codec NONE only (ZIP and BLOSC compressed files are refused, saying so); grids of type Float
// only (others refused by their type's name), with a transform that is a positive scale and a
// translation. Newer files (NanoVDB 32.5 and later, OpenVDB 11: other magic numbers and layouts) are
// refused with their version.
//
// The grid's active voxels (leaf voxels and active tiles of any level) are densified into the box
// that holds them; inactive voxels in it read as the grid's background value. The file is hostile
// input: every offset and count is checked against the bytes before use, each node is reached at
// most once, and the lattice is within limits::kMaxGridVoxels (docs/limits.md).
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "media/sampled_grid.h"

namespace penumbra {

// The float grid named `gridName` of the NanoVDB file `file` (the first of that name, as NanoVDB's
// io::readGrid finds it). Throws InputError naming the file on any bad input: not a regular file,
// over limits::kMaxVolumeFileBytes, not NanoVDB, a version or codec not read, no such grid (the
// message lists those the file holds), another type than float, a malformed grid.
DensityGrid readNanoVdbGrid(const std::filesystem::path& file, const std::string& gridName);

// The same from the file's bytes; `fileForMessages` names them in errors.
DensityGrid readNanoVdbGridBytes(std::span<const std::byte> bytes, const std::string& fileForMessages,
                                 const std::string& gridName);

// The names of the grids the NanoVDB file holds (of any type), in the file's order. Throws as
// readNanoVdbGrid does for a file that cannot be read.
std::vector<std::string> readNanoVdbGridNames(const std::filesystem::path& file);

}  // namespace penumbra
