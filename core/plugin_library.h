// Loading a plugin library once per process: dlopen with RTLD_LOCAL, so that the symbols of what
// it links (OpenImageIO and the libraries under it) stay inside it, then its one entry point,
// which returns its table of functions; the table's first member, `version`, must be the one this
// program was built with. The handle is never closed. The image and texture plugins are loaded
// this way (film/image_plugin_loader.h, textures/texture_plugin_loader.h).
#pragma once

#include <filesystem>

namespace penumbra {

namespace detail {

// The library's function named `entry`. Throws InputError naming the file when the library or the
// function cannot be loaded ("cannot load the WHAT: ...").
void* openPluginEntry(const std::filesystem::path& path, const char* entry, const char* what);
[[noreturn]] void throwPluginOfAnotherVersion(const std::filesystem::path& path, const char* what,
                                              int expected);

}  // namespace detail

// The table of the plugin at `path`; throws InputError naming the file when it cannot be loaded
// or is of another version than `version`.
template <typename Table>
const Table& loadPlugin(const std::filesystem::path& path, const char* entry, const char* what, int version) {
    // Called through its own type (const Table* (*)()), as UBSan's function check requires.
    const auto function = reinterpret_cast<const Table* (*)()>(detail::openPluginEntry(path, entry, what));
    const Table* table = function();
    if (!table || table->version != version) detail::throwPluginOfAnotherVersion(path, what, version);
    return *table;
}

}  // namespace penumbra
