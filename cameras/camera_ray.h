// What a projection makes of a film position and a lens sample: a ray in camera space (+x to the
// image's right, +y up, +z forward) and its weight. The weight is 1 for the ideal cameras; a lens
// system weighs its rays by the radiometry of the film (cameras/lens_system.h), and a ray that
// leaves no light (vignetted, or outside a fisheye's circle) has weight 0.
#pragma once

#include "core/vec.h"

namespace penumbra {

struct CameraSpaceRay {
    Vec3f origin;
    Vec3f direction;  // not necessarily normalized
    float weight = 1.0f;
};

// Film position (raster space: x right, y down, (0, 0) the top-left corner, (width, height) the
// bottom-right) as a point of [-1, 1] x [-1, 1] scaled by the half extents: the image plane's
// coordinates with +y up.
inline Vec2f rasterToScreen(Vec2f filmPosition, float invWidth, float invHeight, float halfWidth,
                            float halfHeight) {
    return {(2.0f * filmPosition.x * invWidth - 1.0f) * halfWidth,
            (1.0f - 2.0f * filmPosition.y * invHeight) * halfHeight};
}

}  // namespace penumbra
