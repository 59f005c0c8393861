// The orthographic projection (pbrt-v4's OrthographicCamera): parallel rays along the view
// direction from the image rectangle, `orthographicHeight` scene units high; with an aperture,
// a thin lens of that radius focused `focusDistance` ahead, as the perspective one.
#pragma once

#include "cameras/aperture.h"
#include "cameras/camera_params.h"
#include "cameras/camera_ray.h"
#include "core/error.h"

namespace penumbra {

class OrthographicProjection {
public:
    OrthographicProjection(const CameraParams& p, float focusDistance, int filmWidth, int filmHeight)
        : halfHeight_(0.5f * p.orthographicHeight),
          halfWidth_(halfHeight_ * float(filmWidth) / float(filmHeight)),
          invWidth_(1.0f / float(filmWidth)),
          invHeight_(1.0f / float(filmHeight)),
          apertureRadius_(p.apertureRadius),
          focusDistance_(focusDistance),
          aperture_(Aperture::ofThinLens(p)) {
        if (!(p.orthographicHeight > 0.0f)) throw InputError("camera: an orthographic height must be > 0");
    }

    CameraSpaceRay generate(Vec2f filmPosition, Vec2f lensSample) const {
        const Vec2f screen = rasterToScreen(filmPosition, invWidth_, invHeight_, halfWidth_, halfHeight_);
        const Vec3f onImage{screen.x, screen.y, 0.0f};
        if (!(apertureRadius_ > 0.0f)) return {onImage, {0.0f, 0.0f, 1.0f}};
        // The lens is centred on the pixel's parallel ray (pbrt-v4 centres it on the axis, which
        // moves every defocused pixel towards the image centre).
        const Vec2f lens = aperture_.sample(lensSample) * apertureRadius_;
        const Vec3f origin = onImage + Vec3f{lens.x, lens.y, 0.0f};
        return {origin, onImage + Vec3f{0.0f, 0.0f, focusDistance_} - origin};
    }
    bool usesLensSample() const { return apertureRadius_ > 0.0f; }
    // The distance between neighbouring pixels, in scene units.
    float pixelSpacing() const { return 2.0f * halfHeight_ * invHeight_; }

private:
    float halfHeight_, halfWidth_;
    float invWidth_, invHeight_;
    float apertureRadius_;
    float focusDistance_;
    Aperture aperture_;
};

}  // namespace penumbra
