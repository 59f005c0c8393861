// Moving a ray origin off a surface so the new ray does not hit the surface it leaves.
// Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection" (Ray Tracing
// Gems, 2019): offset by a few ULPs along the normal in integer space, which scales with the
// magnitude of the coordinates, with a small fixed offset near the origin where ULPs vanish.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "core/vec.h"

namespace penumbra {

// `normal` is the geometric normal on the side the new ray leaves towards.
inline Vec3f offsetRayOrigin(Vec3f point, Vec3f normal) {
    constexpr float kOriginRadius = 1.0f / 32.0f;
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;
    Vec3f result;
    for (int axis = 0; axis < 3; ++axis) {
        const float p = point[axis];
        const int32_t offsetUlps = int32_t(kIntScale * normal[axis]);
        const float shifted =
            std::bit_cast<float>(std::bit_cast<int32_t>(p) + (p < 0.0f ? -offsetUlps : offsetUlps));
        result[axis] = std::abs(p) < kOriginRadius ? p + kFloatScale * normal[axis] : shifted;
    }
    return result;
}

}  // namespace penumbra
