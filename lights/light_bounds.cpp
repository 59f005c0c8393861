#include "lights/light_bounds.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra {

namespace {

// The cone about `axis` of half-angle acos(cosTheta); cosTheta -1 is every direction.
struct Cone {
    Vec3f axis;
    float cosTheta;
};

Cone unionOf(Cone a, Cone b) {
    if (a.cosTheta <= -1.0f) return a;
    if (b.cosTheta <= -1.0f) return b;
    constexpr double kPi = std::numbers::pi;
    const double thetaA = std::acos(std::clamp(double(a.cosTheta), -1.0, 1.0));
    const double thetaB = std::acos(std::clamp(double(b.cosTheta), -1.0, 1.0));
    // The angle between the axes from its sine and cosine: acos of a float dot product near 1
    // would lose small angles entirely.
    const double ax = a.axis.x, ay = a.axis.y, az = a.axis.z, bx = b.axis.x, by = b.axis.y, bz = b.axis.z;
    const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    const double thetaD = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz);
    if (std::min(thetaD + thetaB, kPi) <= thetaA) return a;
    if (std::min(thetaD + thetaA, kPi) <= thetaB) return b;
    // The cone whose edge touches both cones' far edges, its axis between theirs.
    const double thetaO = 0.5 * (thetaA + thetaD + thetaB);
    const Vec3f perpendicular = cross(a.axis, b.axis);
    const float perpendicularLength = length(perpendicular);
    if (thetaO >= kPi || !(perpendicularLength > 0.0f)) return {a.axis, -1.0f};
    // a's axis turned by thetaO - thetaA towards b's about their common perpendicular (Rodrigues;
    // the perpendicular is orthogonal to the axis turned).
    const double thetaR = thetaO - thetaA;
    const Vec3f k = perpendicular / perpendicularLength;
    const Vec3f axis = a.axis * float(std::cos(thetaR)) + cross(k, a.axis) * float(std::sin(thetaR));
    const float axisLength = length(axis);
    if (!(axisLength > 0.0f)) return {a.axis, -1.0f};
    // Widened by 1e-4 radians, far beyond the float axis's rounding.
    return {axis / axisLength, float(std::cos(std::min(thetaO + 1e-4, kPi)))};
}

}  // namespace

LightBounds unionOf(const LightBounds& a, const LightBounds& b) {
    if (!(a.phi > 0.0f)) return b;
    if (!(b.phi > 0.0f)) return a;
    LightBounds u;
    const float distance = length(b.center - a.center);
    if (distance + b.radius <= a.radius) {
        u.center = a.center;
        u.radius = a.radius;
    } else if (distance + a.radius <= b.radius) {
        u.center = b.center;
        u.radius = b.radius;
    } else {
        const float radius = 0.5f * (distance + a.radius + b.radius);
        u.center = a.center + (b.center - a.center) * ((radius - a.radius) / distance);
        // Widened relatively and by the centre's own rounding (a few ulps of its coordinates).
        const float centerScale =
            std::max({std::abs(u.center.x), std::abs(u.center.y), std::abs(u.center.z)});
        u.radius = radius * 1.0001f + centerScale * 1e-6f;
    }
    const Cone cone = unionOf(Cone{a.axis, a.cosThetaO}, Cone{b.axis, b.cosThetaO});
    u.axis = cone.axis;
    u.cosThetaO = cone.cosTheta;
    u.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);
    u.phi = a.phi + b.phi;
    u.twoSided = a.twoSided || b.twoSided;
    return u;
}

template <size_t Capacity>
void LightBoundsBatchOf<Capacity>::set(size_t i, const LightBounds& b, float nearestDistanceSquared) {
    centerX_[i] = b.center.x;
    centerY_[i] = b.center.y;
    centerZ_[i] = b.center.z;
    radius_[i] = b.radius;
    radiusSquared_[i] = b.radius * b.radius;
    nearestDistanceSquared_[i] = nearestDistanceSquared;
    axisX_[i] = b.axis.x;
    axisY_[i] = b.axis.y;
    axisZ_[i] = b.axis.z;
    phi_[i] = b.phi;
    cosThetaO_[i] = b.cosThetaO;
    sinThetaO_[i] = safeSqrt(1.0f - b.cosThetaO * b.cosThetaO);
    cosThetaE_[i] = b.cosThetaE;
    twoSided_[i] = b.twoSided ? 1.0f : 0.0f;
    used_ = std::max(used_, (i / kLanes + 1) * kLanes);
}

// Vectorized by GCC under `omp simd` (-fopenmp-simd; bench/README.md, "Speed tricks").
template <size_t Capacity>
void LightBoundsBatchOf<Capacity>::importances(Vec3f p, Vec3f n, float* out) const {
#pragma omp simd
    for (size_t i = 0; i < used_; ++i)
        out[i] = detail::lightImportance(p.x, p.y, p.z, n.x, n.y, n.z, centerX_[i], centerY_[i], centerZ_[i],
                                         radius_[i], radiusSquared_[i], axisX_[i], axisY_[i], axisZ_[i],
                                         phi_[i], cosThetaO_[i], sinThetaO_[i], cosThetaE_[i], twoSided_[i],
                                         nearestDistanceSquared_[i]);
}

template class LightBoundsBatchOf<8>;
template class LightBoundsBatchOf<16>;

}  // namespace penumbra
