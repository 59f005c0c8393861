// The shading frames of the triangles of a scene's still meshes, computed once per render: a hit
// on a still mesh then reads its unit normal and the orthonormal frame around it instead of
// computing a cross product, a square root and two divisions on the path's critical chain, for
// 36 bytes per triangle. The frame serves shading wherever the shading normal is the triangle's
// own (meshes without vertex normals). Meshes that move or deform are not tabulated: their normals
// change over the shutter and are computed at the hit as before. Instanced meshes are tabulated
// once per prototype, in object space, however many instances place them: a hit on an instance
// reads its prototype triangle's normal there and transforms it to the world.
#pragma once

#include <cstdint>
#include <vector>

#include "core/check.h"
#include "core/frame.h"
#include "core/vec.h"
#include "geometry/scene_geometry.h"

namespace penumbra {

// The unit normal of triangle (p0, p1, p2) on its front side, cross(p1 - p0, p2 - p0) normalized;
// the zero vector for a degenerate triangle. The table and the hit-time path both use this, so
// they give the same bits.
inline Vec3f triangleNormal(Vec3f p0, Vec3f p1, Vec3f p2) {
    const Vec3f n = cross(p1 - p0, p2 - p0);
    const float nLength = length(n);
    return nLength > 0.0f ? n / nLength : Vec3f{0.0f, 0.0f, 0.0f};
}

class FaceFrames {
public:
    explicit FaceFrames(const SceneGeometry& scene);

    // Triangle `triangle` of mesh `mesh`'s Frame::fromNormal(triangleNormal(...)) (its n is the
    // normal), or null when the mesh is not tabulated (it moves or deforms, or is not a mesh). A
    // degenerate triangle's n is the zero vector and its s and t mean nothing.
    const Frame* find(uint32_t mesh, uint32_t triangle) const {
        if (mesh >= byMesh_.size() || byMesh_[mesh].empty()) return nullptr;
        PENUMBRA_CHECK(triangle < byMesh_[mesh].size(), "a hit's triangle is one of its mesh's");
        return &byMesh_[mesh][triangle];
    }

    // The same for triangle `triangle` of prototype `prototype` (SceneGeometry::prototypes), in
    // the prototype's own space; prototypes never move, so every one is tabulated.
    const Frame* findPrototype(uint32_t prototype, uint32_t triangle) const {
        PENUMBRA_CHECK(prototype < byPrototype_.size() && triangle < byPrototype_[prototype].size(),
                       "a hit's triangle is one of its prototype's");
        return &byPrototype_[prototype][triangle];
    }

private:
    std::vector<std::vector<Frame>> byMesh_;
    std::vector<std::vector<Frame>> byPrototype_;
};

}  // namespace penumbra
