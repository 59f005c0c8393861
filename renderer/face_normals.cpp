#include "renderer/face_normals.h"

namespace penumbra {

FaceNormals::FaceNormals(const Scene& scene) : byMesh_(scene.meshes.size()) {
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (mesh.motion.moves() || mesh.deforms()) continue;
        std::vector<Vec3f>& normals = byMesh_[m];
        normals.resize(mesh.triangleCount());
        for (size_t t = 0; t < normals.size(); ++t) {
            const uint32_t* index = &mesh.indices[3 * t];
            normals[t] = triangleNormal(mesh.positions[index[0]], mesh.positions[index[1]], mesh.positions[index[2]]);
        }
    }
}

}  // namespace penumbra
