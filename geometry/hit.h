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

}  // namespace penumbra
