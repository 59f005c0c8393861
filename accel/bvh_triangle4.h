// Four watertight ray/triangle tests at once with SSE: the test of geometry/triangle.h (Woop,
// Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013), one triangle per
// lane, for the leaves of our BVH (accel/bvh_accelerator.h). Embree tests leaves the same way.
//
// Every lane performs the scalar test's float operations in the same order, and SSE's add, sub,
// mul and div round exactly as scalar ones do, so each lane's outcome (hit or not, t and the
// barycentrics) is bit for bit the scalar test's. The one branch of the scalar test, the
// recomputation in double when an edge function is exactly zero, is not done here: such lanes
// are reported to the caller, which runs the scalar test on them. The file that includes this
// one is compiled with -ffp-contract=off, like the scalar test's (products must not be fused).
#pragma once

#include <emmintrin.h>
#include <xmmintrin.h>

#include "geometry/triangle.h"

namespace penumbra {

// Four triangles: data[3 * vertex + axis][lane], the vertices p0, p1, p2 as in the scalar test.
using TriangleLanes = float[9][4];

// WatertightRay with each value broadcast to four lanes.
struct WatertightRay4 {
    int kx, ky, kz;
    __m128 ox, oy, oz, sx, sy, sz;

    explicit WatertightRay4(const WatertightRay& r)
        : kx(r.kx),
          ky(r.ky),
          kz(r.kz),
          ox(_mm_set1_ps(r.ox)),
          oy(_mm_set1_ps(r.oy)),
          oz(_mm_set1_ps(r.oz)),
          sx(_mm_set1_ps(r.sx)),
          sy(_mm_set1_ps(r.sy)),
          sz(_mm_set1_ps(r.sz)) {}
};

struct TriangleHits4 {
    alignas(16) float t[4], b1[4], b2[4];
    int hit;       // bit i: lane i hits within [tMin, tMax] (valid only outside `fallback`)
    int fallback;  // bit i: an edge function of lane i is exactly zero; run the scalar test on it
};

inline void intersectTrianglesWatertight4(const WatertightRay4& r, const TriangleLanes& v, float tMin,
                                          float tMax, TriangleHits4& out) {
    const __m128 zero = _mm_setzero_ps();
    // Vertices relative to the ray origin, permuted so the ray runs along z, then sheared.
    const __m128 z0 = _mm_sub_ps(_mm_load_ps(v[0 + r.kz]), r.oz);
    const __m128 z1 = _mm_sub_ps(_mm_load_ps(v[3 + r.kz]), r.oz);
    const __m128 z2 = _mm_sub_ps(_mm_load_ps(v[6 + r.kz]), r.oz);
    const __m128 x0 = _mm_add_ps(_mm_sub_ps(_mm_load_ps(v[0 + r.kx]), r.ox), _mm_mul_ps(r.sx, z0));
    const __m128 y0 = _mm_add_ps(_mm_sub_ps(_mm_load_ps(v[0 + r.ky]), r.oy), _mm_mul_ps(r.sy, z0));
    const __m128 x1 = _mm_add_ps(_mm_sub_ps(_mm_load_ps(v[3 + r.kx]), r.ox), _mm_mul_ps(r.sx, z1));
    const __m128 y1 = _mm_add_ps(_mm_sub_ps(_mm_load_ps(v[3 + r.ky]), r.oy), _mm_mul_ps(r.sy, z1));
    const __m128 x2 = _mm_add_ps(_mm_sub_ps(_mm_load_ps(v[6 + r.kx]), r.ox), _mm_mul_ps(r.sx, z2));
    const __m128 y2 = _mm_add_ps(_mm_sub_ps(_mm_load_ps(v[6 + r.ky]), r.oy), _mm_mul_ps(r.sy, z2));

    // Edge functions.
    const __m128 e0 = _mm_sub_ps(_mm_mul_ps(x1, y2), _mm_mul_ps(y1, x2));
    const __m128 e1 = _mm_sub_ps(_mm_mul_ps(x2, y0), _mm_mul_ps(y2, x0));
    const __m128 e2 = _mm_sub_ps(_mm_mul_ps(x0, y1), _mm_mul_ps(y0, x1));
    out.fallback = _mm_movemask_ps(
        _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)), _mm_cmpeq_ps(e2, zero)));

    // Rejected: the origin outside an edge (some e < 0 and some e > 0), det == 0, the hit behind
    // the origin, or t outside [tMin, tMax] (NaN fails every comparison, as in the scalar test).
    const __m128 anyNegative =
        _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)), _mm_cmplt_ps(e2, zero));
    const __m128 anyPositive =
        _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)), _mm_cmpgt_ps(e2, zero));
    const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
    const __m128 tScaled =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, _mm_mul_ps(z0, r.sz)), _mm_mul_ps(e1, _mm_mul_ps(z1, r.sz))),
                   _mm_mul_ps(e2, _mm_mul_ps(z2, r.sz)));
    const __m128 detNegative = _mm_cmplt_ps(det, zero);
    const __m128 behind = _mm_or_ps(_mm_and_ps(detNegative, _mm_cmpgt_ps(tScaled, zero)),
                                    _mm_andnot_ps(detNegative, _mm_cmplt_ps(tScaled, zero)));
    const __m128 invDet = _mm_div_ps(_mm_set1_ps(1.0f), det);
    const __m128 t = _mm_mul_ps(tScaled, invDet);
    const __m128 inRange = _mm_and_ps(_mm_cmpge_ps(t, _mm_set1_ps(tMin)), _mm_cmple_ps(t, _mm_set1_ps(tMax)));
    const __m128 rejected =
        _mm_or_ps(_mm_or_ps(_mm_and_ps(anyNegative, anyPositive), _mm_cmpeq_ps(det, zero)), behind);
    out.hit = _mm_movemask_ps(_mm_andnot_ps(rejected, inRange)) & ~out.fallback;
    if (out.hit != 0) {  // t beyond its error bound (watertightTError), lane by lane as there
        const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        const auto abs4 = [&](__m128 a) { return _mm_and_ps(a, absMask); };
        const auto max3 = [&](__m128 a, __m128 b, __m128 c) {
            return _mm_max_ps(_mm_max_ps(abs4(a), abs4(b)), abs4(c));
        };
        const __m128 maxXt = max3(x0, x1, x2), maxYt = max3(y0, y1, y2);
        const __m128 maxZ = max3(z0, z1, z2);
        const __m128 maxZt = max3(_mm_mul_ps(z0, r.sz), _mm_mul_ps(z1, r.sz), _mm_mul_ps(z2, r.sz));
        const __m128 maxE = max3(e0, e1, e2);
        const __m128 deltaZ = _mm_mul_ps(_mm_set1_ps(gamma(3)), maxZt);
        const __m128 deltaX = _mm_mul_ps(_mm_set1_ps(gamma(5)), _mm_add_ps(maxXt, maxZ));
        const __m128 deltaY = _mm_mul_ps(_mm_set1_ps(gamma(5)), _mm_add_ps(maxYt, maxZ));
        const __m128 deltaE =
            _mm_mul_ps(_mm_set1_ps(2.0f),
                       _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gamma(2)), maxXt), maxYt),
                                             _mm_mul_ps(deltaY, maxXt)),
                                  _mm_mul_ps(deltaX, maxYt)));
        const __m128 sum = _mm_add_ps(
            _mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gamma(3)), maxE), maxZt), _mm_mul_ps(deltaE, maxZt)),
            _mm_mul_ps(deltaZ, maxE));
        const __m128 tError = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(3.0f), sum), abs4(invDet));
        out.hit &= _mm_movemask_ps(_mm_cmpnle_ps(t, tError));  // !(t <= tError), as the scalar test
    }
    _mm_store_ps(out.t, t);
    _mm_store_ps(out.b1, _mm_mul_ps(e1, invDet));
    _mm_store_ps(out.b2, _mm_mul_ps(e2, invDet));
}

}  // namespace penumbra
