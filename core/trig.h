// sin and cos of an angle in [-pi/4, pi/4] by short polynomials (the minimax coefficients of
// Cephes' sinf/cosf, within about one ulp there). Cheaper than a libm call for the warps that need
// only this range, and the same bits on every machine (libm picks its code by CPU features).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/vec.h"

namespace penumbra {

// sqrt and asin of a value that rounding may have pushed just outside their domain
// (1 - cos^2 slightly below 0, a sine slightly beyond 1).
inline float safeSqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
inline float safeAsin(float x) { return std::asin(std::clamp(x, -1.0f, 1.0f)); }

// (cos a, sin a) for |a| <= pi / 4.
[[gnu::always_inline]] inline Vec2f cosSinQuarterPi(float a) {
    const float z = a * a;
    const float sine = a + a * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
    const float cosine =
        1.0f - 0.5f * z +
        z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
    return {cosine, sine};
}

// (cos, sin) of the angle 2 pi u, for u in [0, 1] (a uniform azimuth): the nearest quarter turn
// exactly (4u minus its nearest integer is exact), and the rest, within pi / 4, by the polynomials.
[[gnu::always_inline]] inline Vec2f cosSinTurn(float u) {
    const float quarters = 4.0f * u;
    const float nearest = std::nearbyint(quarters);
    const Vec2f cs = cosSinQuarterPi((quarters - nearest) * (std::numbers::pi_v<float> / 2.0f));
    switch (int(nearest) & 3) {
        case 0:
            return cs;
        case 1:
            return {-cs.y, cs.x};
        case 2:
            return {-cs.x, -cs.y};
        default:
            return {cs.y, -cs.x};
    }
}

}  // namespace penumbra
