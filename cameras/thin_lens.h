// The thin-lens perspective projection (Cook et al. 1984; pbrt's PerspectiveCamera): rays leave a
// point of the aperture and pass through the point of the focus plane that the film position
// images to. With a zero aperture it is a pinhole.
#pragma once

#include "cameras/aperture.h"
#include "cameras/camera_params.h"
#include "cameras/camera_ray.h"

namespace penumbra {

class ThinLensProjection {
public:
    // `focusDistance` is the resolved one (> 0).
    ThinLensProjection(const CameraParams& params, float focusDistance, int filmWidth, int filmHeight);

    CameraSpaceRay generate(Vec2f filmPosition, Vec2f lensSample) const {
        // Point on the image plane at z = 1.
        const Vec2f screen = rasterToScreen(filmPosition, invWidth_, invHeight_, halfWidth_, halfHeight_);
        const Vec3f onImagePlane{screen.x, screen.y, 1.0f};
        if (!(apertureRadius_ > 0.0f)) return {{0.0f, 0.0f, 0.0f}, onImagePlane};
        // Every ray through the lens converges on the focus plane where the pinhole ray meets it.
        const Vec2f lens = aperture_.sample(lensSample) * apertureRadius_;
        const Vec3f origin{lens.x, lens.y, 0.0f};
        return {origin, onImagePlane * focusDistance_ - origin};
    }
    bool usesLensSample() const { return apertureRadius_ > 0.0f; }
    // The distance between neighbouring pixels on the image plane at z = 1.
    float pixelSpacing() const { return 2.0f * halfHeight_ * invHeight_; }

private:
    float halfHeight_ = 1.0f;  // of the image plane at z = 1
    float halfWidth_ = 1.0f;
    float invWidth_ = 1.0f, invHeight_ = 1.0f;
    float apertureRadius_ = 0.0f;
    float focusDistance_ = 1.0f;
    Aperture aperture_;
};

}  // namespace penumbra
