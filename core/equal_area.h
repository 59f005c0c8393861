// Clarberg's equal-area map between the square and the sphere ("Fast Equal-Area Mapping of the
// (Hemi)Sphere using SIMD", 2008), as pbrt-v4 uses it for its environment maps and goniometric
// lights: pbrt-v4's EqualAreaSquareToSphere and EqualAreaSphereToSquare.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/sampling.h"
#include "core/vec.h"

namespace penumbra {

// Clarberg's equal-area map of the square [0, 1]^2 onto the unit sphere, with c towards the pole
// of the square's centre, and its inverse (with atan2 where pbrt-v4 uses a polynomial fit).
// Directions given to the inverse are unit vectors.
inline Vec3f equalAreaSquareToSphere(Vec2f st) {
    const float u = 2.0f * st.x - 1.0f, v = 2.0f * st.y - 1.0f;
    const float up = std::abs(u), vp = std::abs(v);
    const float signedDistance = 1.0f - (up + vp);  // from the diagonal |u| + |v| = 1
    const float r = 1.0f - std::abs(signedDistance);
    const float phi = (r == 0.0f ? 1.0f : (vp - up) / r + 1.0f) * (0.25f * kPi);
    const float c = std::copysign(1.0f - r * r, signedDistance);
    const float ring = r * std::sqrt(std::max(0.0f, 2.0f - r * r));
    return {std::copysign(std::cos(phi), u) * ring, std::copysign(std::sin(phi), v) * ring, c};
}

inline Vec2f equalAreaSphereToSquare(Vec3f d) {
    const float x = std::abs(d.x), y = std::abs(d.y), z = std::abs(d.z);
    // r = sqrt(1 - |z|), with 1 - |z| from the other components: no cancellation near the poles.
    const float r = std::sqrt((x * x + y * y) / (1.0f + z));
    const float phi = std::atan2(y, x) * (2.0f * kInvPi);  // in [0, 1]
    float v = phi * r, u = r - v;
    if (d.z < 0.0f) {
        std::swap(u, v);
        u = 1.0f - u;
        v = 1.0f - v;
    }
    u = std::copysign(u, d.x);
    v = std::copysign(v, d.y);
    return {0.5f * (u + 1.0f), 0.5f * (v + 1.0f)};
}

}  // namespace penumbra
