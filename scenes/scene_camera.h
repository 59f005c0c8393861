// The scene's camera description turned into the camera that generates rays.
#pragma once

#include "cameras/camera.h"
#include "scenes/scene.h"

namespace penumbra {

inline ThinLensCamera makeSceneCamera(const Scene& scene) {
    const CameraDesc& c = scene.camera;
    ThinLensCameraParams p;
    p.lookFrom = c.lookFrom;
    p.lookAt = c.lookAt;
    p.up = c.up;
    p.motion = c.motion;
    p.verticalFovDegrees = c.verticalFovDegrees;
    p.apertureRadius = c.apertureRadius;
    p.focusDistance = c.focusDistance;
    p.apertureBlades = c.apertureBlades;
    p.apertureRotationDegrees = c.apertureRotationDegrees;
    p.filmWidth = scene.film.width;
    p.filmHeight = scene.film.height;
    return ThinLensCamera(p);
}

}  // namespace penumbra
