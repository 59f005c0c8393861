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

    // translate(translation) * rotation * scale(scale) and its inverse, written out: the same bits
    // as the products of the 4x4 factors (Matrix4::operator*, in double), without them. A hit on
    // a moving shape needs it (bench/README.md, "Speed tricks").
    Transform toTransform() const {
        const Matrix4 r = rotation.toMatrix();
        const Vec3f inverseScale{1.0f / scale.x, 1.0f / scale.y, 1.0f / scale.z};
        Matrix4 m = Matrix4::identity(), inverse = Matrix4::identity();
        for (int i = 0; i < 3; ++i) {
            // (rotation^T * translate(-translation)) row i, last column: the factors' product's rounding.
            double back = 0.0;
            for (int k = 0; k < 3; ++k) back += double(r.m[k][i]) * double(-translation[k]);
            for (int j = 0; j < 3; ++j) {
                m.m[i][j] = exactProduct(r.m[i][j], scale[j]);
                inverse.m[i][j] = exactProduct(inverseScale[i], r.m[j][i]);
            }
            m.m[i][3] = translation[i] + 0.0f;
            inverse.m[i][3] = exactProduct(inverseScale[i], float(back));
        }
        return {m, inverse};
    }

private:
    // a * b rounded once, and a zero always +0, as a sum of products in double started at +0 gives it.
    static float exactProduct(float a, float b) { return float(double(a) * double(b) + 0.0); }
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
