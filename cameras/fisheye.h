// The fisheye projection: the directions within half the field of view of the view direction
// onto the disk inscribed in the image's shorter side, by the angle theta from the view direction:
// image radius proportional to theta (equidistant) or to sin(theta / 2) (equisolid angle: every
// pixel the same solid angle), as Cycles' fisheye panoramas. The field of view spans the disk's
// diameter, up to 360 degrees; pixels beyond it (the image's corners) see what lies further out,
// as far as the mapping reaches (theta = 180 degrees), and are black beyond.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "cameras/camera_params.h"
#include "cameras/camera_ray.h"
#include "core/error.h"
#include "core/sampling.h"

namespace penumbra {

class FisheyeProjection {
public:
    FisheyeProjection(const CameraParams& p, int filmWidth, int filmHeight)
        : mapping_(p.fisheyeMapping),
          halfFov_(0.5f * p.verticalFovDegrees * kPi / 180.0f),
          centre_{0.5f * float(filmWidth), 0.5f * float(filmHeight)},
          invRadius_(2.0f / float(std::min(filmWidth, filmHeight))),
          sinQuarterFov_(std::sin(0.5f * halfFov_)) {
        if (!(p.verticalFovDegrees > 0.0f && p.verticalFovDegrees <= 360.0f))
            throw InputError("camera: a fisheye's fov must lie in (0, 360] degrees");
    }

    CameraSpaceRay generate(Vec2f filmPosition, Vec2f /*lensSample*/) const {
        // Offset from the centre in units of the disk's radius, +y up.
        const float x = (filmPosition.x - centre_.x) * invRadius_,
                    y = (centre_.y - filmPosition.y) * invRadius_;
        const float r = std::sqrt(x * x + y * y);
        const std::optional<float> theta = angleAt(r);
        if (!theta) return {{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f};
        const float sinTheta = std::sin(*theta);
        // The direction in the plane of the axis and the offset; the centre looks straight ahead.
        const float cosPhi = r > 0.0f ? x / r : 1.0f, sinPhi = r > 0.0f ? y / r : 0.0f;
        return {{0.0f, 0.0f, 0.0f}, {sinTheta * cosPhi, sinTheta * sinPhi, std::cos(*theta)}};
    }
    bool usesLensSample() const { return false; }
    // The angle between neighbouring pixels at the image centre (radians).
    float pixelSpacing() const {
        const float slope = mapping_ == FisheyeMapping::Equidistant ? halfFov_ : 2.0f * sinQuarterFov_;
        return slope * invRadius_;
    }

    // The angle from the view direction at image radius r (1: the disk's edge); nullopt beyond
    // what the mapping reaches.
    std::optional<float> angleAt(float r) const {
        float theta;
        if (mapping_ == FisheyeMapping::Equidistant) {
            theta = r * halfFov_;
        } else {
            const float s = r * sinQuarterFov_;
            if (!(s <= 1.0f)) return std::nullopt;
            theta = 2.0f * std::asin(s);
        }
        if (!(theta <= kPi)) return std::nullopt;
        return theta;
    }

private:
    FisheyeMapping mapping_;
    float halfFov_;
    Vec2f centre_;
    float invRadius_;
    float sinQuarterFov_;
};

}  // namespace penumbra
