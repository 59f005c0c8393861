#include "media/openvdb_grid.h"

#include <array>

#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/plugin_library.h"
#include "core/resource_paths.h"
#include "media/volume_plugin.h"

namespace penumbra {

namespace {

const PenumbraVolumePlugin& volumePlugin() {
    static const PenumbraVolumePlugin& plugin = []() -> const PenumbraVolumePlugin& {
        return loadPlugin<PenumbraVolumePlugin>(pluginPath(PENUMBRA_VOLUME_PLUGIN_FILE),
                                                PENUMBRA_VOLUME_PLUGIN_ENTRY, "volume plugin",
                                                kPenumbraVolumePluginVersion);
    }();  // a failed load is retried on the next call
    return plugin;
}

}  // namespace

DensityGrid readOpenVdbGrid(const std::filesystem::path& path, const std::string& gridName) {
    // OpenVDB opens the file by its path: it is checked first to be a regular file (not a FIFO,
    // which would block, or a device) within the size limit.
    { InputFile check(path, "OpenVDB file", limits::kMaxVolumeFileBytes); }
    const PenumbraVolumePlugin& plugin = volumePlugin();
    DensityGrid grid;
    PenumbraVolumeGrid read{};
    std::array<char, 1024> message{};
    const auto store = [](void* context, const float* values, size_t count) {
        static_cast<DensityGrid*>(context)->values.assign(values, values + count);
    };
    const std::string file = path.string();
    if (!plugin.readOpenVdbGrid(file.c_str(), gridName.c_str(), &read, store, &grid, message.data(),
                                message.size()))
        throwFileError(path, message.data());
    grid.nx = read.nx;
    grid.ny = read.ny;
    grid.nz = read.nz;
    grid.bounds = {{read.lower[0], read.lower[1], read.lower[2]},
                   {read.upper[0], read.upper[1], read.upper[2]}};
    PENUMBRA_CHECK(grid.values.size() == size_t(grid.nx) * size_t(grid.ny) * size_t(grid.nz),
                   "the volume plugin stores nx * ny * nz values");
    return grid;
}

}  // namespace penumbra
