// A triangle mesh as the scene gives it: positions, optional normals and uvs, its material, its
// emission and its motion.
//
// Motion: times are shutter fractions (0 = shutter open, 1 = closed), the same as Ray::time.
// A mesh with a moving `motion` transform keeps its geometry in object space and is placed in the
// world by motion.at(time); otherwise its geometry is in world space.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/motion.h"
#include "core/vec.h"
#include "geometry/emission.h"
#include "geometry/medium_interface.h"
#include "textures/texture.h"

namespace penumbra {

struct TriangleMesh {
    std::string name;               // for messages: the scene's JSON pointer or the file name
    std::vector<Vec3f> positions;   // world space, or object space when `motion` moves; the first
                                    // deformation key when there are several
    std::vector<Vec3f> normals;     // optional, per vertex, world space, unit length
    std::vector<Vec2f> uvs;         // optional, per vertex
    std::vector<uint32_t> indices;  // three per triangle; front face is counter-clockwise,
                                    // i.e. its normal is cross(p1 - p0, p2 - p0)
    uint32_t material = 0;          // index into Scene::materials
    Emission emission;
    // Deformation: empty, or >= 2 arrays of positions (the first equal to `positions`), evenly
    // spaced over the shutter and interpolated linearly per vertex.
    std::vector<std::vector<Vec3f>> positionKeys;
    MotionTransform motion;
    MediumInterface media{};  // the media on its two sides (none: not a boundary)
    // A cut-out (geometry/cut_out.h): the surface's coverage over its (u, v); null: opaque.
    std::shared_ptr<const Texture> alpha;

    size_t triangleCount() const { return indices.size() / 3; }
    bool deforms() const { return positionKeys.size() >= 2; }
    bool moves() const { return deforms() || motion.moves(); }
};

// The (u, v) of a mesh's triangle `index` (its three vertex indices) at barycentrics (b1, b2) of
// its vertices 1 and 2, for shading (geometry/surface_interaction.h) and cut-outs: (0, 0) on a
// mesh without uvs.
inline Vec2f meshUvAt(const std::vector<Vec2f>& uvs, const uint32_t* index, float b1, float b2) {
    if (uvs.empty()) return {0.0f, 0.0f};
    return uvs[index[0]] * (1.0f - b1 - b2) + uvs[index[1]] * b1 + uvs[index[2]] * b2;
}

}  // namespace penumbra
