#include "textures/texture_plugin_loader.h"

#include <dlfcn.h>

#include <atomic>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"
#include "core/resource_paths.h"

namespace penumbra {

namespace {

std::atomic<bool> loaded{false};

const PenumbraTexturePlugin& load() {
    const std::filesystem::path path = texturePluginPath();
    SourceLocation where;
    where.file = path.string();
    // RTLD_LOCAL: OpenImageIO's symbols stay inside the plugin. The handle is never closed.
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw InputError(where, fmt::format("cannot load the texture plugin: {}", ::dlerror()));
    auto entry = reinterpret_cast<PenumbraTexturePluginEntry>(::dlsym(handle, PENUMBRA_TEXTURE_PLUGIN_ENTRY));
    if (!entry) throw InputError(where, fmt::format("cannot load the texture plugin: {}", ::dlerror()));
    const PenumbraTexturePlugin* plugin = entry();
    if (!plugin || plugin->version != kPenumbraTexturePluginVersion)
        throw InputError(where, fmt::format("the texture plugin is of another version (expected {})",
                                            kPenumbraTexturePluginVersion));
    loaded = true;
    return *plugin;
}

}  // namespace

std::filesystem::path texturePluginPath() { return pluginPath(PENUMBRA_TEXTURE_PLUGIN_FILE); }

const PenumbraTexturePlugin& texturePlugin() {
    static const PenumbraTexturePlugin& plugin = load();  // a failed load is retried on the next call
    return plugin;
}

bool texturePluginLoaded() { return loaded; }

}  // namespace penumbra
