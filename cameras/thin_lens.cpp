#include "cameras/thin_lens.h"

#include <cmath>

#include "core/error.h"
#include "core/sampling.h"

namespace penumbra {

ThinLensProjection::ThinLensProjection(const CameraParams& p, float focusDistance, int filmWidth,
                                       int filmHeight) {
    if (!(p.verticalFovDegrees > 0.0f && p.verticalFovDegrees < 180.0f))
        throw InputError("camera: fov must lie in (0, 180) degrees");
    halfHeight_ = std::tan(0.5f * p.verticalFovDegrees * kPi / 180.0f);
    halfWidth_ = halfHeight_ * float(filmWidth) / float(filmHeight);
    invWidth_ = 1.0f / float(filmWidth);
    invHeight_ = 1.0f / float(filmHeight);
    apertureRadius_ = p.apertureRadius;
    focusDistance_ = focusDistance;
    aperture_ = Aperture::ofThinLens(p);
}

}  // namespace penumbra
