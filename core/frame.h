// Orthonormal frame around a unit normal; converts between world and local shading space,
// where the normal is +z.
#pragma once

#include <cmath>

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

    Vec3f toLocal(Vec3f v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3f toWorld(Vec3f v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace penumbra
