// The scene file's "lights" section: lights without a shape, one reader per type in one table
// (light_reader.cpp). Emitting shapes (shape_reader.h) and the environment
// (environment_reader.h) are read with their own concepts. scenes/README.md documents the keys.
#pragma once

#include <filesystem>

#include "scenes/json_reader.h"
#include "scenes/scene.h"

namespace penumbra {

// Adds the section's lights to `scene`, in file order.
// Files they name (IES profiles) are relative to `folder`.
void readLights(const JsonValue& section, const std::filesystem::path& folder, Scene& scene);

}  // namespace penumbra
