// Moving a ray origin off a surface so the new ray does not hit the surface it leaves.
// Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection" (Ray Tracing
// Gems, 2019): offset by a few ULPs along the normal in integer space, which scales with the
// magnitude of the coordinates, with a small fixed offset near the origin where ULPs vanish.
#pragma once

#include <emmintrin.h>

#include "core/vec.h"

namespace penumbra {

// `normal` is the geometric normal on the side the new ray leaves towards. The three axes are
// done at once with SSE2, lane for lane the same operations as one axis in scalar code.
inline Vec3f offsetRayOrigin(Vec3f point, Vec3f normal) {
    constexpr float kOriginRadius = 1.0f / 32.0f;
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;
    const __m128 p = _mm_setr_ps(point.x, point.y, point.z, 0.0f);
    const __m128 n = _mm_setr_ps(normal.x, normal.y, normal.z, 0.0f);
    // The offset in ULPs, negated for negative coordinates (whose bits grow the other way).
    const __m128i offsetUlps = _mm_cvttps_epi32(_mm_mul_ps(_mm_set1_ps(kIntScale), n));
    const __m128i negative = _mm_castps_si128(_mm_cmplt_ps(p, _mm_setzero_ps()));
    const __m128i signedUlps = _mm_sub_epi32(_mm_xor_si128(offsetUlps, negative), negative);
    const __m128 shifted = _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(p), signedUlps));
    // Near the origin, where ULPs vanish, a fixed offset instead.
    const __m128 absP = _mm_andnot_ps(_mm_set1_ps(-0.0f), p);
    const __m128 nearOrigin = _mm_cmplt_ps(absP, _mm_set1_ps(kOriginRadius));
    const __m128 fixed = _mm_add_ps(p, _mm_mul_ps(_mm_set1_ps(kFloatScale), n));
    const __m128 result = _mm_or_ps(_mm_and_ps(nearOrigin, fixed), _mm_andnot_ps(nearOrigin, shifted));
    alignas(16) float out[4];
    _mm_store_ps(out, result);
    return {out[0], out[1], out[2]};
}

}  // namespace penumbra
