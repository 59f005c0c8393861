// Moving a ray origin off a surface so the new ray does not hit the surface it leaves (pbrt-v4,
// Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th ed., section 6.8.6). The computed
// point p lies within the box p +- pointError of the true surface point; the plane through the
// true point with normal n then lies within dot(|n|, pointError) of p along n, so moving p that far
// along n puts it on the normal's side of the surface, and rounding the sum away from p keeps it
// there (a step is taken even when the error is 0, so the origin always leaves the surface).
// Intersection tests reject hits within their own error of the origin (geometry/triangle.h),
// so a ray cannot hit the surface it leaves however large or small the coordinates are: the offset
// follows the error of the point, not fixed constants.
#pragma once

#include <emmintrin.h>

#include <algorithm>
#include <limits>

#include "core/float_error.h"
#include "core/simd.h"
#include "core/vec.h"

namespace penumbra {

// 2^-40: far below a float's resolution of the point's other coordinates (2^-24 of the largest),
// so no surface lies within it; it keeps the moved coordinate a normal float for every point whose
// largest coordinate exceeds 2^-86 (about 1e-26).
inline constexpr float kMinimumRelativeOffset = 0x1p-40f;

// How far offsetRayOrigin moves `point` along `normal` (either side: the distance is the same for
// n and -n). `pointError`: a bound on the absolute error of each coordinate of `point`.
[[gnu::always_inline]] inline float offsetDistance(Vec3f point, Vec3f pointError, Vec3f normal) {
    // 1 + gamma(8) covers the rounding of d and of n d, and |n| a few ulps short of 1. A point
    // without rounding error along n (on a plane through 0 whose vertices have that coordinate
    // exactly 0) would move by 0 and leave with a coordinate of the smallest normal float, on which
    // Embree's traversal runs markedly slower; the distance is therefore at least
    // kMinimumRelativeOffset of the point's largest coordinate (bench/README.md, "Speed tricks").
    return std::max(dot(abs(normal), pointError) * (1.0f + gamma(8)),
                    maxComponent(abs(point)) * kMinimumRelativeOffset);
}

// `point` moved by `d` (offsetDistance) along `normal` and one float further. The three axes are
// done at once with SSE2.
[[gnu::always_inline]] inline Vec3f offsetAlong(Vec3f point, Vec3f normal, float d) {
    const __m128 n = toLanes(normal);
    const __m128 moved = _mm_add_ps(toLanes(point), _mm_mul_ps(n, _mm_set1_ps(d)));
    // One float further along n: the bits grow by one where moved and n have the same sign (away
    // from zero) and shrink by one where not; nothing where n is 0.
    const __m128i bits = _mm_castps_si128(moved);
    const __m128i opposite = _mm_srai_epi32(_mm_xor_si128(bits, _mm_castps_si128(n)), 31);  // 0 or -1
    const __m128i alongN = _mm_castps_si128(_mm_cmpneq_ps(n, _mm_setzero_ps()));
    const __m128i step = _mm_and_si128(_mm_or_si128(opposite, _mm_set1_epi32(1)), alongN);
    const __m128 stepped = _mm_castsi128_ps(_mm_add_epi32(bits, step));
    // Embree runs with denormals read as zero: a zero or subnormal origin would lie on the surface,
    // so it becomes the smallest normal float on n's side (stepping a zero would not do either).
    const __m128 signMask = _mm_set1_ps(-0.0f), smallest = _mm_set1_ps(std::numeric_limits<float>::min());
    const __m128 tiny =
        _mm_and_ps(_mm_cmplt_ps(_mm_andnot_ps(signMask, moved), smallest), _mm_castsi128_ps(alongN));
    const __m128 replacement = _mm_or_ps(_mm_and_ps(n, signMask), smallest);
    const __m128 result = _mm_or_ps(_mm_and_ps(tiny, replacement), _mm_andnot_ps(tiny, stepped));
    return toVec3f(result);
}

// `normal`: the geometric normal, on the side the new ray leaves towards; `pointError`: a bound on
// the absolute error of each coordinate of `point`.
[[gnu::always_inline]] inline Vec3f offsetRayOrigin(Vec3f point, Vec3f pointError, Vec3f normal) {
    return offsetAlong(point, normal, offsetDistance(point, pointError, normal));
}

}  // namespace penumbra
