#include "geometry/face_frames.h"

namespace penumbra {

namespace {

std::vector<Frame> tabulate(const TriangleMesh& mesh) {
    std::vector<Frame> frames(mesh.triangleCount());
    for (size_t t = 0; t < frames.size(); ++t) {
        const uint32_t* index = &mesh.indices[3 * t];
        frames[t] = Frame::fromNormal(
            triangleNormal(mesh.positions[index[0]], mesh.positions[index[1]], mesh.positions[index[2]]));
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
