// The scene file's "camera" section: a pinhole or thin-lens camera, possibly moving over the
// shutter (camera_reader.cpp). scenes/README.md documents the keys.
#pragma once

#include "cameras/camera.h"
#include "scenes/json_reader.h"

namespace penumbra {

// The camera the "camera" object describes; missing keys keep ThinLensCameraParams' defaults.
ThinLensCameraParams readCamera(const JsonValue& value);

}  // namespace penumbra
