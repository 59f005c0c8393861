// The unit geometric normals of the triangles of a scene's still meshes, computed once per render:
// a hit on a still mesh then reads its normal instead of computing a cross product, a square root
// and a division on the path's critical chain (about 2% of a Cornell box render's time), for 12
// bytes per triangle. Meshes that move or deform are not tabulated: their normals change over the
// shutter and are computed at the hit as before.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec.h"
#include "scenes/scene.h"

namespace penumbra {

// The unit normal of triangle (p0, p1, p2) on its front side, cross(p1 - p0, p2 - p0) normalized;
// the zero vector for a degenerate triangle. The table and the hit-time path both use this, so
// they give the same bits.
inline Vec3f triangleNormal(Vec3f p0, Vec3f p1, Vec3f p2) {
    const Vec3f n = cross(p1 - p0, p2 - p0);
    const float nLength = length(n);
    return nLength > 0.0f ? n / nLength : Vec3f{0.0f, 0.0f, 0.0f};
}

class FaceNormals {
public:
    explicit FaceNormals(const Scene& scene);

    // Triangle `primId` of mesh `geomId`'s normal, or null when the mesh is not tabulated (it moves
    // or deforms, or is not a mesh).
    const Vec3f* find(uint32_t geomId, uint32_t primId) const {
        if (geomId >= byMesh_.size() || byMesh_[geomId].empty()) return nullptr;
        return &byMesh_[geomId][primId];
    }

private:
    std::vector<std::vector<Vec3f>> byMesh_;
};

}  // namespace penumbra
