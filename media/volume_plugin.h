// The volume plugin's C interface: the OpenVDB reader (media/openvdb_library_reader.h) in a
// library of its own (penumbra_volume_plugin, in lib/penumbra/), loaded the first time a scene
// names a .vdb file (media/openvdb_grid.cpp). Linked into the program, OpenVDB and the libraries
// under it cost every run of penumbra about 35 ms of start-up resolving their symbols, scenes
// without volumes included (bench/README.md). A C interface, as the texture plugin's: nothing of
// C++ (exceptions, the standard library's types) crosses it.
#pragma once

#include <stddef.h>

extern "C" {

// A lattice as DensityGrid holds it: nx * ny * nz values over the box [lower, upper].
struct PenumbraVolumeGrid {
    int nx, ny, nz;
    float lower[3], upper[3];
};

struct PenumbraVolumePlugin {
    int version;  // kPenumbraVolumePluginVersion
    // Reads the float grid `gridName` of the OpenVDB file `path` (a regular file within the size
    // limit: the caller checks). On success returns 1, fills `*grid` and calls `store(context,
    // values, count)` once with its nx * ny * nz values (x fastest); otherwise returns 0 with the
    // reason in `message` (NUL-terminated, cut at messageSize bytes), which does not name the file.
    int (*readOpenVdbGrid)(const char* path, const char* gridName, PenumbraVolumeGrid* grid,
                           void (*store)(void* context, const float* values, size_t count), void* context,
                           char* message, size_t messageSize);
};

#define PENUMBRA_VOLUME_PLUGIN_ENTRY "penumbra_volume_plugin"

}  // extern "C"

constexpr int kPenumbraVolumePluginVersion = 1;
