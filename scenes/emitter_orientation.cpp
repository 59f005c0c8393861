#include "scenes/emitter_orientation.h"

#include <fmt/format.h>

namespace penumbra {

namespace {

// Whether anything of the scene besides `self` (a still mesh's vertex, a sphere's nearest point)
// lies strictly on the front side of the plane through `at` with normal `normal`.
bool anythingInFront(const Scene& scene, const TriangleMesh& self, Vec3f at, Vec3f normal) {
    const Vec3f n = normalize(normal);
    for (const TriangleMesh& mesh : scene.meshes) {
        if (&mesh == &self) continue;
        for (const Vec3f& p : mesh.positions)
            if (dot(n, p - at) > 1e-4f) return true;
    }
    for (const Sphere& s : scene.spheres)
        if (dot(n, s.center - at) + s.radius > 1e-4f) return true;
    return !scene.prototypes.empty();  // instances: where they lie is not worked out here
}

}  // namespace

std::vector<std::string> emittersFacingAway(const Scene& scene) {
    std::vector<std::string> messages;
    for (const TriangleMesh& mesh : scene.meshes) {
        // Moving meshes are in their own space: where they face depends on the time.
        if (!mesh.emission.emits() || mesh.emission.twoSided || mesh.moves()) continue;
        Vec3f normalSum, weightedCentre;
        float area = 0.0f;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Vec3f p0 = mesh.positions[mesh.indices[3 * t]],
                        p1 = mesh.positions[mesh.indices[3 * t + 1]],
                        p2 = mesh.positions[mesh.indices[3 * t + 2]];
            const Vec3f n = cross(p1 - p0, p2 - p0);  // twice the area, along the front normal
            const float a = length(n);
            normalSum += n;
            weightedCentre += (p0 + p1 + p2) * (a / 3.0f);
            area += a;
        }
        if (!(area > 0.0f) || !(length(normalSum) > 1e-3f * area)) continue;  // closed or flat-folded
        const Vec3f at = weightedCentre / area;
        if (dot(normalSum, scene.camera.lookFrom - at) > 0.0f || anythingInFront(scene, mesh, at, normalSum))
            continue;
        messages.push_back(fmt::format(
            "{}: emits on its front side only, and nothing of the scene, not even the camera, lies on that "
            "side; if it should light the scene, set \"two_sided\": true or give its corners in the other "
            "order",
            mesh.name));
    }
    return messages;
}

}  // namespace penumbra
