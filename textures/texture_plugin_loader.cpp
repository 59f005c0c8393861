#include "textures/texture_plugin_loader.h"

#include <atomic>

#include "core/plugin_library.h"
#include "core/resource_paths.h"

namespace penumbra {

namespace {

std::atomic<bool> loaded{false};

const PenumbraTexturePlugin& load() {
    const PenumbraTexturePlugin& plugin = loadPlugin<PenumbraTexturePlugin>(
        texturePluginPath(), PENUMBRA_TEXTURE_PLUGIN_ENTRY, "texture plugin", kPenumbraTexturePluginVersion);
    loaded = true;
    return plugin;
}

}  // namespace

std::filesystem::path texturePluginPath() { return pluginPath(PENUMBRA_TEXTURE_PLUGIN_FILE); }

const PenumbraTexturePlugin& texturePlugin() {
    static const PenumbraTexturePlugin& plugin = load();  // a failed load is retried on the next call
    return plugin;
}

bool texturePluginLoaded() { return loaded; }

}  // namespace penumbra
