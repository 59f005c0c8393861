#include "geometry/face_frames.h"

#include <cmath>

#include "core/check.h"

namespace penumbra {

namespace {

// Whether `f` is orthonormal to within `tolerance`, or its n is not a unit vector (a degenerate
// triangle's zero normal, or one whose tiny cross product lost its precision in subnormals).
[[maybe_unused]] bool isOrthonormalOrNotUnit(const Frame& f, float tolerance) {
    if (!(std::abs(dot(f.n, f.n) - 1.0f) <= 1e-4f)) return true;
    return std::abs(dot(f.s, f.s) - 1.0f) <= tolerance && std::abs(dot(f.t, f.t) - 1.0f) <= tolerance &&
           std::abs(dot(f.s, f.t)) <= tolerance && std::abs(dot(f.s, f.n)) <= tolerance &&
           std::abs(dot(f.t, f.n)) <= tolerance;
}

std::vector<Frame> tabulate(const TriangleMesh& mesh) {
    std::vector<Frame> frames(mesh.triangleCount());
    for (size_t t = 0; t < frames.size(); ++t) {
        const uint32_t* index = &mesh.indices[3 * t];
        frames[t] = Frame::fromNormal(
            triangleNormal(mesh.positions[index[0]], mesh.positions[index[1]], mesh.positions[index[2]]));
        PENUMBRA_CHECK(isOrthonormalOrNotUnit(frames[t], 1e-3f),
                       "a unit normal's shading frame is orthonormal");
    }
    return frames;
}

}  // namespace

FaceFrames::FaceFrames(const SceneGeometry& scene) : byMesh_(scene.meshes.size()) {
    for (size_t m = 0; m < scene.meshes.size(); ++m)
        if (!scene.meshes[m].moves()) byMesh_[m] = tabulate(scene.meshes[m]);
    byPrototype_.reserve(scene.prototypes.size());
    for (const TriangleMesh& prototype : scene.prototypes) byPrototype_.push_back(tabulate(prototype));
}

}  // namespace penumbra
