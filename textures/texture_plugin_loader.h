// Loading the texture plugin (textures/texture_plugin.h) on first use: only scenes that name an
// image file load it, and with it OpenImageIO.
#pragma once

#include <filesystem>

#include "textures/texture_plugin.h"

namespace penumbra {

// Where the plugin is looked for: where CMake built it, otherwise beside the running executable.
std::filesystem::path texturePluginPath();

// The plugin's functions, loaded once per process. Throws InputError naming the plugin's file
// when it cannot be loaded.
const PenumbraTexturePlugin& texturePlugin();

// True once texturePlugin() has loaded the plugin (for tests and for the summary's statistics).
bool texturePluginLoaded();

}  // namespace penumbra
