// Moving a ray origin off a surface so the new ray does not hit the surface it leaves (pbrt-v4,
// Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th ed., section 6.8.6). The computed
// point p lies within the box p +- pointError of the true surface point; the plane through the
// true point with normal n then lies within dot(|n|, pointError) of p along n, so moving p that far
// along n puts it on the normal's side of the surface, and rounding the sum away from p keeps it
// there (a step is taken even when the error is 0, so the origin always leaves the surface).
// Intersection tests reject hits within their own error of the origin (geometry/ray_triangle.h),
// so a ray cannot hit the surface it leaves however large or small the coordinates are: the offset
// follows the error of the point, not fixed constants.
#pragma once

#include <cmath>
#include <limits>

#include "core/float_error.h"
#include "core/vec.h"

namespace penumbra {

// `normal`: the geometric normal, on the side the new ray leaves towards; `pointError`: a bound on
// the absolute error of each coordinate of `point`.
inline Vec3f offsetRayOrigin(Vec3f point, Vec3f pointError, Vec3f normal) {
    // 1 + gamma(8) covers the rounding of d and of n d, and |n| a few ulps short of 1.
    const float d = dot(abs(normal), pointError) * (1.0f + gamma(8));
    const Vec3f offset = normal * d;
    Vec3f moved = point + offset;
    for (int axis = 0; axis < 3; ++axis) {
        if (normal[axis] > 0.0f) moved[axis] = nextFloatUp(moved[axis]);
        else if (normal[axis] < 0.0f) moved[axis] = nextFloatDown(moved[axis]);
        // Embree runs with denormals read as zero: a subnormal origin would lie on the surface.
        if (normal[axis] != 0.0f && std::abs(moved[axis]) < std::numeric_limits<float>::min())
            moved[axis] = std::copysign(std::numeric_limits<float>::min(), normal[axis]);
    }
    return moved;
}

}  // namespace penumbra
