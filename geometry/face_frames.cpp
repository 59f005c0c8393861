#include "geometry/face_frames.h"

namespace penumbra {

FaceFrames::FaceFrames(const SceneGeometry& scene) : byMesh_(scene.meshes.size()) {
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (mesh.moves()) continue;
        std::vector<Frame>& frames = byMesh_[m];
        frames.resize(mesh.triangleCount());
        for (size_t t = 0; t < frames.size(); ++t) {
            const uint32_t* index = &mesh.indices[3 * t];
            frames[t] = Frame::fromNormal(
                triangleNormal(mesh.positions[index[0]], mesh.positions[index[1]], mesh.positions[index[2]]));
        }
    }
}

}  // namespace penumbra
