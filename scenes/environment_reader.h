// The scene file's light from infinitely far away: "background" (a constant) or "environment" (a
// constant or an HDR image), one reader per environment type in one table
// (environment_reader.cpp). scenes/README.md documents the keys.
#pragma once

#include <filesystem>

#include "lights/environment_light.h"
#include "scenes/json_reader.h"

namespace penumbra {

// "background": a colour arriving from every direction.
EnvironmentLight readBackground(const JsonValue& value);

// "environment": {"type": "constant" | "image", ...}. A relative image path is relative to
// `folder` (the scene file's).
EnvironmentLight readEnvironment(const JsonValue& value, const std::filesystem::path& folder);

}  // namespace penumbra
