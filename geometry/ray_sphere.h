// Ray/sphere intersection with the precision improvements of Haines, Günther and Akenine-Möller,
// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, chapter 7, 2019):
//  - the discriminant is r^2 - |l|^2, with l the vector from the centre to the point of the ray's
//    line closest to it, instead of b^2 - ac, which cancels catastrophically for small spheres far
//    from the origin;
//  - the two roots are c / q and q / a with q = b + sign(b) sqrt(discriminant), so neither is the
//    difference of two nearly equal numbers.
// Embree's sphere points use the same closest-point formulation, so both backends round alike.
#pragma once

#include <cmath>
#include <utility>

#include "core/vec.h"

namespace penumbra {

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

}  // namespace penumbra
