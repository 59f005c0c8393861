// Object motion over the camera shutter: a list of poses (keys) evenly spaced in time, from the
// shutter opening (first key) to its closing (last key). Between keys, scale and translation are
// interpolated linearly and the rotation by slerp, so a spinning object turns rather than
// shrinks, as with Embree's quaternion motion instances, which the Embree backend is given.
// Times here are shutter fractions in [0, 1], the same as Ray::time.
#pragma once

#include <algorithm>
#include <vector>

#include "core/quaternion.h"
#include "core/transform.h"
#include "core/vec.h"

namespace penumbra {

// One pose: p -> translation + rotation * (scale * p).
struct TransformKey {
    Vec3f scale{1.0f, 1.0f, 1.0f};
    Quaternion rotation;
    Vec3f translation{0.0f, 0.0f, 0.0f};

    Transform toTransform() const {
        return Transform::translate(translation) * Transform(rotation.toMatrix(), rotation.toMatrix().transposed()) *
               Transform::scale(scale);
    }
};

// Where `time` falls between evenly spaced keys: the segment and the fraction within it.
struct KeySegment {
    size_t first;
    float fraction;
};
inline KeySegment locateKeySegment(size_t keyCount, float time) {
    if (keyCount < 2) return {0, 0.0f};
    const float scaled = std::clamp(time, 0.0f, 1.0f) * float(keyCount - 1);
    const size_t first = std::min(size_t(scaled), keyCount - 2);
    return {first, scaled - float(first)};
}

struct MotionTransform {
    std::vector<TransformKey> keys;  // empty or a single key: no motion

    bool moves() const { return keys.size() >= 2; }

    TransformKey keyAt(float time) const {
        if (keys.empty()) return {};
        if (keys.size() == 1) return keys.front();
        const KeySegment s = locateKeySegment(keys.size(), time);
        const TransformKey& a = keys[s.first];
        const TransformKey& b = keys[s.first + 1];
        const float t = s.fraction;
        TransformKey k;
        k.scale = a.scale * (1.0f - t) + b.scale * t;
        k.rotation = slerp(a.rotation, b.rotation, t);
        k.translation = a.translation * (1.0f - t) + b.translation * t;
        return k;
    }
    Transform at(float time) const { return keyAt(time).toTransform(); }
};

// Per-vertex positions at `time` from evenly spaced deformation keys.
inline Vec3f interpolateKeys(const std::vector<std::vector<Vec3f>>& keys, uint32_t vertex, float time) {
    const KeySegment s = locateKeySegment(keys.size(), time);
    if (keys.size() < 2) return keys.front()[vertex];
    return keys[s.first][vertex] * (1.0f - s.fraction) + keys[s.first + 1][vertex] * s.fraction;
}

}  // namespace penumbra
