// What a traversal backend reports for a ray's closest hit. Which shape and primitive the ids
// name is decided by SceneGeometry::shapeOf (geometry/scene_geometry.h), the one owner of that rule.
#pragma once

#include <cstdint>

#include "core/vec.h"

namespace penumbra {

struct Hit {
    float t = 0.0f;
    float u = 0.0f, v = 0.0f;  // triangle barycentrics of vertices 1 and 2
    Vec3f geometricNormal;     // as the backend reports it: not normalized, orientation unspecified
                               // (for an instance, Embree reports it in the prototype's space)
    uint32_t geomId = 0;
    uint32_t primId = 0;
};

// The triangle a ray leaves, by its hit ids. A ray leaving a flat triangle cannot meet it again,
// so a hit on it is rounding: a backend whose triangle test has no error bound of its own
// (Embree's) skips it. None for camera rays and rays leaving spheres, which can meet their sphere
// again from inside.
struct TriangleLeft {
    static constexpr uint32_t kNone = ~0u;
    uint32_t geomId = kNone;
    uint32_t primId = 0;
    bool isNone() const { return geomId == kNone; }
};

}  // namespace penumbra
