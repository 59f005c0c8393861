#include "film/image_plugin_loader.h"

#include <dlfcn.h>

#include <atomic>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"
#include "core/resource_paths.h"

namespace penumbra {

namespace {

std::atomic<bool> loaded{false};

const PenumbraImagePlugin& load() {
    const std::filesystem::path path = imagePluginPath();
    SourceLocation where;
    where.file = path.string();
    // RTLD_LOCAL: OpenImageIO's symbols stay inside the plugin. The handle is never closed.
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw InputError(where, fmt::format("cannot load the image plugin: {}", ::dlerror()));
    auto entry = reinterpret_cast<PenumbraImagePluginEntry>(::dlsym(handle, PENUMBRA_IMAGE_PLUGIN_ENTRY));
    if (!entry) throw InputError(where, fmt::format("cannot load the image plugin: {}", ::dlerror()));
    const PenumbraImagePlugin* plugin = entry();
    if (!plugin || plugin->version != kPenumbraImagePluginVersion)
        throw InputError(where, fmt::format("the image plugin is of another version (expected {})",
                                            kPenumbraImagePluginVersion));
    loaded = true;
    return *plugin;
}

}  // namespace

std::filesystem::path imagePluginPath() { return pluginPath(PENUMBRA_IMAGE_PLUGIN_FILE); }

const PenumbraImagePlugin& imagePlugin() {
    static const PenumbraImagePlugin& plugin = load();  // a failed load is retried on the next call
    return plugin;
}

bool imagePluginLoaded() { return loaded; }

}  // namespace penumbra
