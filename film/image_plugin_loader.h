// Loading the image plugin (film/image_plugin.h) on first use.
#pragma once

#include <filesystem>

#include "film/image_plugin.h"

namespace penumbra {

// Where the plugin is: lib/penumbra/ of the resource prefix (core/resource_paths.h).
std::filesystem::path imagePluginPath();

// The plugin's functions, loaded once per process. Throws InputError naming the plugin's file
// when it cannot be loaded.
const PenumbraImagePlugin& imagePlugin();

// True once imagePlugin() has loaded the plugin (for tests: what must not load it).
bool imagePluginLoaded();

}  // namespace penumbra
