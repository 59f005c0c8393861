// A placement of a prototype mesh (SceneGeometry::prototypes): the mesh is stored and built into
// the traversal structures once, however many times it is placed. Each instance has its own
// placement (a fixed affine transform, or motion keys over the shutter) and its own material.
#pragma once

#include <cstdint>
#include <string>

#include "core/motion.h"
#include "core/transform.h"
#include "geometry/medium_interface.h"

namespace penumbra {

struct MeshInstance {
    std::string name;         // for messages: the scene's JSON pointer
    uint32_t prototype = 0;   // index into SceneGeometry::prototypes
    uint32_t material = 0;    // index into Scene::materials
    Transform placement;      // object to world, when `motion` does not move
    MotionTransform motion;   // >= 2 keys: the placement over the shutter (and `placement` is unused)
    MediumInterface media{};  // the media on its two sides (none: not a boundary)

    bool moves() const { return motion.moves(); }
    // Object to world at `time`. Both backends and the shading code take rays into the prototype's
    // space with this transform's inverse, so that they all compute the same object-space ray.
    Transform toWorld(float time) const { return motion.moves() ? motion.at(time) : placement; }
};

}  // namespace penumbra
