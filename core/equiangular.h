// Equiangular sampling (Kulla and Fajardo, "Importance Sampling Techniques for Path Tracing in
// Participating Media", EGSR 2012): a distance t along the ray origin + t * direction (unit), over
// [0, tEnd), with density proportional to 1 / |origin + t * direction - point|^2, the falloff of
// light from `point`. Uniform in the angle subtended at the point, hence the name:
//   pdf(t) = h / ((thetaB - thetaA) (h^2 + (t - delta)^2)),
//   t(u) = delta + h tan(thetaA + u (thetaB - thetaA)),
// with delta the projection of the point on the ray, h its distance from the ray's line and
// thetaA, thetaB the angles of t = 0 and t = tEnd (pi / 2 for an infinite ray) seen from the point.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/vec.h"

namespace penumbra {

class EquiangularDistance {
public:
    // Invalid (valid() false, and pdf 0 everywhere) where the point lies on the ray's line, within
    // 1e-6 of its distance along the ray: the density would be a spike there.
    EquiangularDistance(Vec3f origin, Vec3f direction, float tEnd, Vec3f point) {
        const Vec3f toPoint = point - origin;
        delta_ = dot(toPoint, direction);
        h_ = length(toPoint - direction * delta_);
        thetaA_ = std::atan2(-delta_, h_);
        thetaB_ = std::isinf(tEnd) ? float(std::numbers::pi / 2) : std::atan2(tEnd - delta_, h_);
        valid_ = h_ > 1e-6f * std::max(1.0f, std::abs(delta_)) && thetaB_ > thetaA_ && std::isfinite(h_);
    }
    bool valid() const { return valid_; }
    float sample(float u) const { return delta_ + h_ * std::tan(thetaA_ + u * (thetaB_ - thetaA_)); }
    float pdf(float t) const {
        if (!valid_) return 0.0f;
        const float s = t - delta_;
        return h_ / ((thetaB_ - thetaA_) * (h_ * h_ + s * s));
    }

private:
    float delta_ = 0.0f, h_ = 0.0f, thetaA_ = 0.0f, thetaB_ = 0.0f;
    bool valid_ = false;
};

}  // namespace penumbra
