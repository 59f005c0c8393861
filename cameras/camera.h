// The thin-lens camera (Cook et al. 1984; pbrt's PerspectiveCamera): rays leave a point on a
// circular lens and pass through the point of the focus plane that the film position images to.
// With a zero aperture it is a pinhole camera. The aperture is a disk, or a regular polygon whose
// vertices lie on the aperture radius (the shape of out-of-focus highlights).
#pragma once

#include <vector>

#include "core/ray.h"
#include "core/transform.h"
#include "core/vec.h"
#include "textures/texture_footprint.h"

namespace penumbra {

// Where the camera is and what it looks at. A moving camera has several poses, evenly spaced over
// the shutter; between them the three points are interpolated linearly.
struct CameraPose {
    Vec3f lookFrom, lookAt, up;
};

// The camera as the scene gives it (scenes/README.md, `camera`).
struct ThinLensCameraParams {
    Vec3f lookFrom{0.0f, 0.0f, 0.0f};
    Vec3f lookAt{0.0f, 0.0f, -1.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    // Camera motion: empty, or >= 2 poses evenly spaced over the shutter, interpolated linearly;
    // they replace lookFrom / lookAt / up.
    std::vector<CameraPose> motion;
    float verticalFovDegrees = 40.0f;
    float apertureRadius = 0.0f;  // lens radius in scene units; 0 is a pinhole
    float focusDistance = 0.0f;   // along the view direction; 0 means |lookAt - lookFrom|
    int apertureBlades = 0;       // 0: a circular aperture; >= 3: a regular polygon (shaped bokeh)
    float apertureRotationDegrees = 0.0f;
    // The shutter interval, in the scene's time unit; motion keys are spread over it. Rays carry
    // the shutter fraction (0 = open, 1 = closed).
    float shutterOpen = 0.0f;
    float shutterClose = 0.0f;
};

class ThinLensCamera {
public:
    // Parameters are validated by the scene loader; throws InputError on degenerate ones anyway.
    ThinLensCamera(const ThinLensCameraParams& params, int filmWidth, int filmHeight);

    // filmPosition in raster space: x to the right, y down, (0, 0) the top-left corner of the
    // image and (width, height) the bottom-right. lensSample and timeSample are uniform in [0, 1);
    // the ray's time is the shutter fraction timeSample.
    Ray generateRay(Vec2f filmPosition, Vec2f lensSample, float timeSample) const;

    // Whether generateRay reads lensSample (a lens of non-zero aperture): a sample that is not read
    // need not be drawn.
    bool usesLensSample() const { return apertureRadius_ > 0.0f; }

    // The camera-to-world transform at a shutter fraction.
    Transform cameraToWorld(float time = 0.0f) const;
    // What a texture lookup's footprint needs of the camera (textures/texture_footprint.h), at
    // shutter open, for `samplesPerPixel` samples per pixel.
    CameraFootprint footprint(int samplesPerPixel) const;

private:
    // A point on the unit aperture (disk or polygon) from a uniform 2D sample.
    Vec2f sampleAperture(Vec2f u) const;

    Transform cameraToWorld_;
    Vec3f pinholeOrigin_;  // cameraToWorld_ applied to the camera-space origin, once
    std::vector<CameraPose> motion_;
    float halfHeight_ = 1.0f;  // of the image plane at z = 1
    float halfWidth_ = 1.0f;
    float apertureRadius_ = 0.0f;
    int apertureBlades_ = 0;
    float apertureRotation_ = 0.0f;  // radians
    std::vector<Vec2f>
        bladeVertices_;  // the polygon's vertices on the unit circle, the first repeated at the end
    float focusDistance_ = 1.0f;
    float invWidth_ = 1.0f, invHeight_ = 1.0f;
};

}  // namespace penumbra
