// The volume plugin (media/volume_plugin.h): OpenVDB's reader behind a C interface. InputError and
// every other exception stop here and travel as a message.
#include "media/volume_plugin.h"

#include <cstring>
#include <exception>
#include <string>

#include "core/error.h"
#include "media/openvdb_library_reader.h"

namespace {

void copyText(const std::string& text, char* out, size_t size) {
    if (!out || size == 0) return;
    const size_t n = std::min(text.size(), size - 1);
    std::memcpy(out, text.data(), n);
    out[n] = '\0';
}

int readOpenVdbGrid(const char* path, const char* gridName, PenumbraVolumeGrid* grid,
                    void (*store)(void*, const float*, size_t), void* context, char* message,
                    size_t messageSize) {
    try {
        const penumbra::DensityGrid read = penumbra::readOpenVdbGridWithLibrary(path, gridName);
        *grid = {read.nx,
                 read.ny,
                 read.nz,
                 {read.bounds.lower.x, read.bounds.lower.y, read.bounds.lower.z},
                 {read.bounds.upper.x, read.bounds.upper.y, read.bounds.upper.z}};
        store(context, read.values.data(), read.values.size());
        return 1;
    } catch (const penumbra::InputError& e) {
        copyText(e.message(), message, messageSize);
    } catch (const std::exception& e) {
        copyText(std::string("cannot read the OpenVDB file: ") + e.what(), message, messageSize);
    } catch (...) {
        copyText("cannot read the OpenVDB file", message, messageSize);
    }
    return 0;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const PenumbraVolumePlugin* penumbra_volume_plugin() {
    static const PenumbraVolumePlugin plugin{kPenumbraVolumePluginVersion, readOpenVdbGrid};
    return &plugin;
}
