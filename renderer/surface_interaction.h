// A shading point rebuilt from a backend's hit. This is shared by all backends so that they
// shade identically: positions come from our own vertex data and barycentrics (or, for spheres,
// the hit reprojected onto the surface), not from origin + t * direction.
#pragma once

#include <cmath>

#include "core/ray.h"
#include "scenes/accelerator.h"
#include "scenes/scene.h"

namespace penumbra {

struct SurfaceInteraction {
    Vec3f position;
    Vec3f geometricNormal;  // unit, on the shape's front side
    Vec3f shadingNormal;    // unit, in the hemisphere of geometricNormal
    Vec2f uv;
    uint32_t material = 0;
    uint32_t geomId = 0, primId = 0;
};

inline SurfaceInteraction makeSurfaceInteraction(const Scene& scene, const Ray& ray, const Hit& hit) {
    SurfaceInteraction si;
    si.geomId = hit.geomId;
    si.primId = hit.primId;
    if (hit.geomId < scene.meshes.size()) {
        const TriangleMesh& mesh = scene.meshes[hit.geomId];
        const uint32_t i0 = mesh.indices[3 * hit.primId], i1 = mesh.indices[3 * hit.primId + 1],
                       i2 = mesh.indices[3 * hit.primId + 2];
        const Vec3f p0 = mesh.positions[i0], p1 = mesh.positions[i1], p2 = mesh.positions[i2];
        const float b1 = hit.u, b2 = hit.v, b0 = 1.0f - b1 - b2;
        si.position = p0 * b0 + p1 * b1 + p2 * b2;
        Vec3f n = cross(p1 - p0, p2 - p0);
        const float nLength = length(n);
        si.geometricNormal = nLength > 0.0f ? n / nLength : normalize(-ray.direction);
        si.shadingNormal = si.geometricNormal;
        if (!mesh.normals.empty()) {
            const Vec3f ns = mesh.normals[i0] * b0 + mesh.normals[i1] * b1 + mesh.normals[i2] * b2;
            const float nsLength = length(ns);
            if (nsLength > 0.0f) si.shadingNormal = faceForward(ns / nsLength, si.geometricNormal);
        }
        if (!mesh.uvs.empty()) si.uv = mesh.uvs[i0] * b0 + mesh.uvs[i1] * b1 + mesh.uvs[i2] * b2;
        si.material = mesh.material;
    } else {
        const Sphere& sphere = scene.spheres[hit.primId];
        Vec3f outward = ray.at(hit.t) - sphere.center;
        const float outwardLength = length(outward);
        outward = outwardLength > 0.0f ? outward / outwardLength : Vec3f{0.0f, 0.0f, 1.0f};
        si.position = sphere.center + outward * sphere.radius;
        si.geometricNormal = outward;
        si.shadingNormal = outward;
        const float phi = std::atan2(outward.y, outward.x);
        si.uv = {phi < 0.0f ? phi / (2.0f * 3.14159265f) + 1.0f : phi / (2.0f * 3.14159265f),
                 std::acos(std::clamp(outward.z, -1.0f, 1.0f)) / 3.14159265f};
        si.material = sphere.material;
    }
    return si;
}

}  // namespace penumbra
