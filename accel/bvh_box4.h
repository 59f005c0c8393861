// A ray against the four child boxes of a 4-wide BVH node (accel/bvh_wide.h) at once, with SSE
// (the x86-64 baseline): the slab test of Kay and Kajiya (1986), with the precomputed reciprocal
// direction and near/far plane selection of Williams et al., "An Efficient and Robust Ray-Box
// Intersection Algorithm" (Journal of Graphics Tools 10(1), 2005).
//
// Conservative: the far slab distances are enlarged by 1 + 2 gamma(3) so that rounding can never
// make a ray that touches a box miss it (Ize, "Robust BVH Ray Traversal", Journal of Computer
// Graphics Techniques 2(2), 2013; pbrt-v4's Bounds3::IntersectP, PBR 4th ed. section 6.8.2).
// Every lane computes exactly what a scalar test would, in the same order: (plane - origin) *
// (1 / direction), times the factor for far planes.
#pragma once

#include <xmmintrin.h>

#include <cmath>

#include "accel/bvh_wide.h"
#include "core/float_error.h"
#include "core/vec.h"

namespace penumbra {

inline constexpr float kBoxFarScale = 1.0f + 2.0f * gamma(3);

// What the box test needs of a ray, computed once per ray.
struct BoxRay4 {
    __m128 origin[3], invDir[3];
    int nearPlane[3], farPlane[3];  // indices into Bvh4Node::bounds: the slab planes met first and last
    __m128 tnear;

    BoxRay4(Vec3f o, Vec3f d, float tMin) : tnear(_mm_set1_ps(tMin)) {
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = _mm_set1_ps(o[axis]);
            invDir[axis] = _mm_set1_ps(1.0f / d[axis]);  // +-infinity for +-0: the comparisons cope
            const bool negative = std::signbit(d[axis]);
            nearPlane[axis] = negative ? axis + 3 : axis;
            farPlane[axis] = negative ? axis : axis + 3;
        }
    }
};

// Tests the ray's [tnear, tFar] against the node's four boxes. Returns a 4-bit mask of the boxes
// met (bit i: child i) and, in tEntry, where the ray enters each. A NaN slab distance (0 * inf:
// the origin on a slab plane of an axis the ray does not move along) is skipped, as the order of
// the operands of maxps/minps makes it (they return the second operand when either is NaN); that
// keeps the test conservative. Empty slots' boxes (lower +inf, upper -inf) are never met.
inline int intersectBoxes4(const Bvh4Node& node, const BoxRay4& r, float tFar, __m128& tEntry) {
    __m128 t0 = r.tnear, t1 = _mm_set1_ps(tFar);
    const __m128 farScale = _mm_set1_ps(kBoxFarScale);
    for (int axis = 0; axis < 3; ++axis) {
        const __m128 nearPlanes = _mm_load_ps(node.bounds[r.nearPlane[axis]]);
        const __m128 farPlanes = _mm_load_ps(node.bounds[r.farPlane[axis]]);
        const __m128 slabNear = _mm_mul_ps(_mm_sub_ps(nearPlanes, r.origin[axis]), r.invDir[axis]);
        const __m128 slabFar =
            _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(farPlanes, r.origin[axis]), r.invDir[axis]), farScale);
        t0 = _mm_max_ps(slabNear, t0);  // slabNear > t0 ? slabNear : t0
        t1 = _mm_min_ps(slabFar, t1);   // slabFar < t1 ? slabFar : t1
    }
    tEntry = t0;
    return _mm_movemask_ps(_mm_cmple_ps(t0, t1));
}

}  // namespace penumbra
