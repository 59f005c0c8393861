// A sphere as the scene gives it, and its maths: the ray test both backends use, its surface
// coordinates, and the sampling of the part a point sees (its area lights, lights/sphere_light.h).
// Its shading point is made with the other shapes' in geometry/surface_interaction.h.
// When its `motion` moves, center and radius are in object space and motion.at(time) places it in
// the world (as for TriangleMesh).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "core/float_error.h"
#include "core/frame.h"
#include "core/motion.h"
#include "core/sampling.h"
#include "core/trig.h"
#include "core/vec.h"
#include "geometry/emission.h"
#include "geometry/medium_interface.h"

namespace penumbra {

struct Sphere {
    std::string name;
    Vec3f center;
    float radius = 1.0f;  // > 0; the front side is the outside
    uint32_t material = 0;
    Emission emission;
    MotionTransform motion;
    MediumInterface media{};  // the media on its two sides (none: not a boundary)
    // Whether hits need the sphere's (u, v): only for a textured material or emission. The loader
    // clears it for the others, which then skip an arctangent and an arccosine per hit.
    bool needsUv = true;
};

// The ray test: ray/sphere intersection with the precision improvements of Haines, Günther and
// Akenine-Möller, "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, chapter 7, 2019):
//  - the discriminant is r^2 - |l|^2, with l the vector from the centre to the point of the ray's
//    line closest to it, instead of b^2 - ac, which cancels catastrophically for small spheres far
//    from the origin;
//  - the two roots are c / q and q / a with q = b + sign(b) sqrt(discriminant), so neither is the
//    difference of two nearly equal numbers.
// Embree's sphere points use the same closest-point formulation, so both backends round alike.
// The nearest t in [tMin, tMax] where origin + t * direction meets the sphere; from inside the
// sphere that is the exit. Returns false when there is none.
inline bool intersectSphere(Vec3f origin, Vec3f direction, Vec3f center, float radius, float tMin, float tMax,
                            float& tHit) {
    const Vec3f f = origin - center;
    const float a = dot(direction, direction);
    const float b = -dot(f, direction);  // the quadratic is a t^2 - 2 b t + c = 0
    const Vec3f l = f + direction * (b / a);
    const float r2 = radius * radius;
    const float discriminantOverA = r2 - dot(l, l);  // (b^2 - ac) / a
    if (!(discriminantOverA >= 0.0f)) return false;
    const float c = dot(f, f) - r2;
    const float q = b + std::copysign(std::sqrt(a * discriminantOverA), b);
    float t0 = c / q, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 >= tMin && t0 <= tMax) {
        tHit = t0;
        return true;
    }
    if (t1 >= tMin && t1 <= tMax) {
        tHit = t1;
        return true;
    }
    return false;  // also when q == 0 made a root NaN
}

// The surface coordinates (u, v) in [0, 1]^2 at the unit outward normal `outward`: u the azimuth
// about +z from +x, v the polar angle from +z.
inline Vec2f sphereUv(Vec3f outward) {
    const float phi = std::atan2(outward.y, outward.x);
    return {phi < 0.0f ? phi / (2.0f * kPi) + 1.0f : phi / (2.0f * kPi),
            std::acos(std::clamp(outward.z, -1.0f, 1.0f)) / kPi};
}

// Below this sin^2 of the cone's half-angle (~1.5 degrees) the cone's maths use a Taylor
// expansion: 1 - cos(theta) cancels in float (pbrt-v4's Sphere::Sample).
inline constexpr float kSmallConeSin2 = 0.00068523f;

struct SpherePointSample {
    Vec3f point;       // on the sphere
    Vec3f normal;      // unit, outward, at point
    Vec3f pointError;  // bound on each coordinate's absolute error of point (core/ray_offset.h)
};

// A point of the sphere as seen from `reference` (u in [0, 1)^2): uniform in the solid angle the
// sphere subtends from outside (pbrt-v4's Sphere::Sample: a direction in the cone, then the point
// that direction meets first), uniform by area from inside. sphereSampleSolidAnglePdf is its density.
inline SpherePointSample sampleSphereSeenFrom(Vec3f center, float radius, Vec3f reference, Vec2f u) {
    SpherePointSample s;
    const Vec3f toCenter = center - reference;
    const float distanceSquared = lengthSquared(toCenter);
    const float radiusSquared = radius * radius;
    if (distanceSquared <= radiusSquared * 1.0001f) {
        s.normal = sampleUniformSphere(u);
        s.point = center + s.normal * radius;
        s.pointError = (abs(center) + abs(s.normal * radius)) * gamma(8);
        return s;
    }
    const float distance = std::sqrt(distanceSquared);
    const float sinThetaMax = radius / distance;
    const float sin2ThetaMax = sinThetaMax * sinThetaMax;
    const float cosThetaMax = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaMax));
    float cosTheta = (cosThetaMax - 1.0f) * u.x + 1.0f;
    float sin2Theta = 1.0f - cosTheta * cosTheta;
    if (sin2ThetaMax < kSmallConeSin2) {
        sin2Theta = sin2ThetaMax * u.x;
        cosTheta = std::sqrt(1.0f - sin2Theta);
    }
    const float cosAlpha =
        sin2Theta / sinThetaMax + cosTheta * std::sqrt(std::max(0.0f, 1.0f - sin2Theta / sin2ThetaMax));
    const float sinAlpha = std::sqrt(std::max(0.0f, 1.0f - cosAlpha * cosAlpha));
    const Vec2f azimuth = cosSinTurn(u.y);
    const Frame frame = Frame::fromNormal(toCenter / distance);
    // Angle alpha is measured at the centre, from the direction back to the reference.
    const Vec3f fromCenter = frame.toWorld({sinAlpha * azimuth.x, sinAlpha * azimuth.y, -cosAlpha});
    s.normal = normalize(fromCenter);
    s.point = center + s.normal * radius;
    s.pointError = (abs(center) + abs(s.normal * radius)) * gamma(8);
    return s;
}

// The solid-angle density with which sampleSphereSeenFrom from `reference` produces `point` (on
// the sphere, and visible from reference when reference is outside).
inline float sphereSampleSolidAnglePdf(Vec3f center, float radius, Vec3f reference, Vec3f point) {
    const Vec3f toPoint = point - reference;
    const float distanceSquared = lengthSquared(toPoint);
    const float centerDistanceSquared = lengthSquared(center - reference);
    const float radiusSquared = radius * radius;
    if (centerDistanceSquared <= radiusSquared * 1.0001f) {
        const Vec3f normal = normalize(point - center);
        const float cosAtSurface = std::abs(dot(normal, toPoint)) / std::sqrt(distanceSquared);
        return areaToSolidAnglePdf(distanceSquared, cosAtSurface, 4.0f * kPi * radiusSquared);
    }
    const float sin2ThetaMax = radiusSquared / centerDistanceSquared;
    const float cosThetaMax = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaMax));
    // The same small-angle expansion as in sampling: 1 - cos(theta_max) ~ sin^2 / 2.
    const float oneMinusCos = sin2ThetaMax < kSmallConeSin2 ? 0.5f * sin2ThetaMax : 1.0f - cosThetaMax;
    return 1.0f / (2.0f * kPi * oneMinusCos);
}

}  // namespace penumbra
