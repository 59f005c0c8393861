// Which participating media lie on the two sides of a shape's surface (pbrt-v4's MediumInterface):
// indices into Scene::media, or kVacuum. A surface with the same medium on both sides (the
// default) is not a boundary between media: a ray crossing or leaving it stays in the medium it
// was in, so shapes inside a fog need not name it. A boundary gives the medium by side: a ray
// leaving towards the geometric normal's side enters `outside`, otherwise `inside`.
#pragma once

#include <cstdint>

#include "core/vec.h"

namespace penumbra {

struct MediumInterface {
    static constexpr uint32_t kVacuum = ~0u;
    uint32_t inside = kVacuum;
    uint32_t outside = kVacuum;

    bool isTransition() const { return inside != outside; }
    // The medium a ray in `direction` from the surface travels through, given the one it was in.
    uint32_t mediumAlong(Vec3f direction, Vec3f geometricNormal, uint32_t current) const {
        if (!isTransition()) return current;
        return dot(direction, geometricNormal) > 0.0f ? outside : inside;
    }
};

}  // namespace penumbra
