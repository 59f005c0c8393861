#include "film/image_plugin_loader.h"

#include <atomic>

#include "core/plugin_library.h"
#include "core/resource_paths.h"

namespace penumbra {

namespace {

std::atomic<bool> loaded{false};

const PenumbraImagePlugin& load() {
    const PenumbraImagePlugin& plugin = loadPlugin<PenumbraImagePlugin>(
        imagePluginPath(), PENUMBRA_IMAGE_PLUGIN_ENTRY, "image plugin", kPenumbraImagePluginVersion);
    loaded = true;
    return plugin;
}

}  // namespace

std::filesystem::path imagePluginPath() { return pluginPath(PENUMBRA_IMAGE_PLUGIN_FILE); }

const PenumbraImagePlugin& imagePlugin() {
    static const PenumbraImagePlugin& plugin = load();  // a failed load is retried on the next call
    return plugin;
}

bool imagePluginLoaded() { return loaded; }

}  // namespace penumbra
