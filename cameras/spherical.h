// The spherical projection: every direction around the camera, as a latitude-longitude
// (equirectangular) image or Clarberg's equal-area square (pbrt-v4's SphericalCamera mappings).
// Both are the environment light's mappings (lights/environment_light.h), so that a spherical
// image rendered by a camera looking along +z with +y up is an environment map of the scene for an
// unrotated environment light: the equirectangular image's centre is the view direction, its
// columns turn to the right, its top row is straight up. `mirrorColumns` reverses the columns (the
// handedness of pbrt-v4's own images).
#pragma once

#include <cmath>

#include "cameras/camera_params.h"
#include "cameras/camera_ray.h"
#include "core/equal_area.h"
#include "core/sampling.h"

namespace penumbra {

class SphericalProjection {
public:
    SphericalProjection(const CameraParams& p, int filmWidth, int filmHeight)
        : mapping_(p.sphericalMapping),
          mirrorColumns_(p.mirrorColumns),
          invWidth_(1.0f / float(filmWidth)),
          invHeight_(1.0f / float(filmHeight)) {}

    CameraSpaceRay generate(Vec2f filmPosition, Vec2f /*lensSample*/) const {
        const float s = filmPosition.x * invWidth_;
        const Vec2f st{mirrorColumns_ ? 1.0f - s : s, filmPosition.y * invHeight_};
        return {{0.0f, 0.0f, 0.0f}, directionAt(st, mapping_)};
    }
    bool usesLensSample() const { return false; }
    // The angle between neighbouring pixels at the image centre (radians).
    float pixelSpacing() const { return 2.0f * kPi * invWidth_; }

    // The camera-space direction of the image point st in [0, 1]^2 (s right, t down).
    static Vec3f directionAt(Vec2f st, SphericalMapping mapping) {
        if (mapping == SphericalMapping::EqualArea) {
            const Vec3f abc = equalAreaSquareToSphere(st);
            return {-abc.x, abc.z, -abc.y};
        }
        const float longitude = 2.0f * kPi * (st.x - 0.5f);  // from the view direction to the right
        const float polar = kPi * st.y;                      // from straight up
        const float sinPolar = std::sin(polar);
        return {sinPolar * std::sin(longitude), std::cos(polar), sinPolar * std::cos(longitude)};
    }

private:
    SphericalMapping mapping_;
    bool mirrorColumns_;
    float invWidth_, invHeight_;
};

}  // namespace penumbra
