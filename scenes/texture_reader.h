// A texture as a scene file gives it (scenes/README.md, "Textures"): an object in place of a
// colour or a number, {"type": "image" | "checkerboard" | "constant", ...}. Image files are opened
// through the texture plugin (textures/texture_plugin.h) when the scene is read, so that a missing
// or unreadable file is an error naming its key.
#pragma once

#include <filesystem>

#include "scenes/json_reader.h"
#include "textures/texture.h"

namespace penumbra {

// Whether `value` gives a texture (an object) rather than a plain value.
inline bool isTextureValue(const JsonValue& value) { return value.json().is_object(); }

// The texture `value` describes; colours (a constant's, the checkerboard's) lie within [min, max].
// Relative image paths are relative to `folder`, the scene file's.
Texture readTexture(const JsonValue& value, const std::filesystem::path& folder, float min, float max);

}  // namespace penumbra
