// The scene file's "camera" section: its pose (possibly moving over the shutter) and its type, one
// of the projections (camera_reader.cpp). scenes/README.md documents the keys.
#pragma once

#include <filesystem>

#include "cameras/camera_params.h"
#include "scenes/json_reader.h"

namespace penumbra {

// The camera the "camera" object describes; missing keys keep CameraParams' defaults. Files it
// names (a lens file, an aperture image) are relative to `folder`, the scene file's.
CameraParams readCamera(const JsonValue& value, const std::filesystem::path& folder);

}  // namespace penumbra
