// The OpenVDB library's side of readOpenVdbGrid (media/openvdb_grid.h): compiled into the volume
// plugin only (media/volume_plugin.h), so that the library and what it links are loaded only when a
// scene names a .vdb file.
#pragma once

#include <string>

#include "media/sampled_grid.h"

namespace penumbra {

// readOpenVdbGrid's work once the file is known to be a regular file within the size limit. Throws
// InputError naming `file`.
DensityGrid readOpenVdbGridWithLibrary(const std::string& file, const std::string& gridName);

}  // namespace penumbra
