// Moving a Vec3f's coordinates between SSE lanes and the struct.
#pragma once

#include <xmmintrin.h>

#include "core/vec.h"

namespace penumbra {

// (v.x, v.y, v.z, 0).
inline __m128 toLanes(Vec3f v) { return _mm_setr_ps(v.x, v.y, v.z, 0.0f); }

// The first three lanes, taken out in registers. Not by storing the vector into a float array
// and reading the floats back: so written, a renderer built by GCC 12 at -O3 rendered different
// images where the hit's fields were kept in registers, and the expected ones with
// -fno-strict-aliasing or at -O1 (bench/README.md, "Speed tricks", setBarycentricPoint).
inline Vec3f toVec3f(__m128 v) {
    return {_mm_cvtss_f32(v), _mm_cvtss_f32(_mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 1, 1, 1))),
            _mm_cvtss_f32(_mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 2, 2, 2)))};
}

}  // namespace penumbra
