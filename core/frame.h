// Orthonormal frame around a unit normal; converts between world and local shading space,
// where the normal is +z.
#pragma once

#include <xmmintrin.h>

#include <cmath>

#include "core/simd.h"
#include "core/vec.h"

namespace penumbra {

struct Frame {
    Vec3f s, t, n;

    // Branchless construction of Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017).
    static Frame fromNormal(Vec3f n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float b = n.x * n.y * a;
        Frame f;
        f.s = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
        f.t = {b, sign + n.y * n.y * a, -n.y};
        f.n = n;
        return f;
    }

    // The frame whose first axis is `x` and normal `z` (unit and perpendicular): a fiber's frame,
    // along a curve's tangent (geometry/curves.h).
    static Frame fromXZ(Vec3f x, Vec3f z) { return {x, cross(z, x), z}; }

    Vec3f toLocal(Vec3f v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3f toWorld(Vec3f v) const { return s * v.x + t * v.y + n * v.z; }
};

// A Frame held in SSE registers, its rows (s, t, n) and its columns, for code that converts several
// vectors with one frame: each conversion is three products and two sums of whole vectors, the
// same operations in the same order per coordinate as Frame's, so the same bits (a speed trick:
// bench/README.md, "Speed tricks").
struct FrameLanes {
    __m128 s, t, n;  // rows
    __m128 x, y, z;  // columns: (s.x, t.x, n.x), (s.y, t.y, n.y), (s.z, t.z, n.z)

    explicit FrameLanes(const Frame& f)
        : s(toLanes(f.s)),
          t(toLanes(f.t)),
          n(toLanes(f.n)),
          x(_mm_setr_ps(f.s.x, f.t.x, f.n.x, 0.0f)),
          y(_mm_setr_ps(f.s.y, f.t.y, f.n.y, 0.0f)),
          z(_mm_setr_ps(f.s.z, f.t.z, f.n.z, 0.0f)) {}

    // Frame::toLocal: (dot(v, s), dot(v, t), dot(v, n)), each dot summed x, y, then z.
    // The frame whose first axis is `x` and normal `z` (unit and perpendicular): a fiber's frame,
    // along a curve's tangent (geometry/curves.h).
    static Frame fromXZ(Vec3f x, Vec3f z) { return {x, cross(z, x), z}; }

    Vec3f toLocal(Vec3f v) const { return combination(x, y, z, v); }
    // Frame::toWorld: s v.x + t v.y + n v.z.
    Vec3f toWorld(Vec3f v) const { return combination(s, t, n, v); }

private:
    // a v.x + b v.y + c v.z, summed in that order.
    static Vec3f combination(__m128 a, __m128 b, __m128 c, Vec3f v) {
        return toVec3f(
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(a, _mm_set1_ps(v.x)), _mm_mul_ps(b, _mm_set1_ps(v.y))),
                       _mm_mul_ps(c, _mm_set1_ps(v.z))));
    }
};

}  // namespace penumbra
