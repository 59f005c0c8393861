// A shading point rebuilt from a backend's hit. This is shared by all backends so that they
// shade identically: positions come from our own vertex data and barycentrics (or, for spheres,
// the hit reprojected onto the surface), not from origin + t * direction.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/motion.h"
#include "core/ray.h"
#include "core/sampling.h"
#include "scenes/accelerator.h"
#include "scenes/ray_sphere.h"
#include "scenes/ray_triangle.h"
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

namespace detail {

inline Vec3f vertexAt(const TriangleMesh& mesh, uint32_t vertex, float time) {
    return mesh.deforms() ? interpolateKeys(mesh.positionKeys, vertex, time) : mesh.positions[vertex];
}

// Moves a point and its normals from object to world space for a moving shape.
inline void placeInWorld(const Transform& toWorld, SurfaceInteraction& si) {
    si.position = toWorld.applyPoint(si.position);
    si.geometricNormal = normalize(toWorld.applyNormal(si.geometricNormal));
    si.shadingNormal = faceForward(normalize(toWorld.applyNormal(si.shadingNormal)), si.geometricNormal);
}

}  // namespace detail

// The same hit whichever backend found it: t and the barycentrics of the primitive the backend
// reports are recomputed with the tests our BVH uses (scenes/ray_triangle.h, ray_sphere.h; moving
// shapes in object space, as the BVH's instances do), so that whenever Embree and the BVH find the
// same primitive everything downstream sees the same bits, and renders with either backend are
// bit-identical unless some hit differs. Embree rounds differently (its Plücker-form test); should
// our test miss the primitive (a ray along an edge), the backend's values stay.
inline void canonicalizeHit(const Scene& scene, const Ray& ray, Hit& hit) {
    Vec3f origin = ray.origin, direction = ray.direction;
    const MotionTransform& motion =
        hit.geomId < scene.meshes.size() ? scene.meshes[hit.geomId].motion : scene.spheres[hit.primId].motion;
    if (motion.moves()) {
        // Into object space exactly as the BVH takes a ray into an instance.
        const Transform toObject = motion.at(ray.time).inverse();
        origin = toObject.applyPoint(ray.origin);
        direction = toObject.applyVector(ray.direction);
    }
    if (hit.geomId < scene.meshes.size()) {
        const TriangleMesh& mesh = scene.meshes[hit.geomId];
        const uint32_t* index = &mesh.indices[3 * size_t(hit.primId)];
        const Vec3f p0 = detail::vertexAt(mesh, index[0], ray.time), p1 = detail::vertexAt(mesh, index[1], ray.time),
                    p2 = detail::vertexAt(mesh, index[2], ray.time);
        const float vertices[9] = {p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z};
        TriangleHit th;
        if (intersectTriangleWatertight(WatertightRay(origin, direction), vertices, ray.tnear, ray.tfar, th)) {
            hit.t = th.t;
            hit.u = th.b1;
            hit.v = th.b2;
        }
    } else {
        const Sphere& sphere = scene.spheres[hit.primId];
        float t;
        if (intersectSphere(origin, direction, sphere.center, sphere.radius, ray.tnear, ray.tfar, t)) hit.t = t;
    }
}

inline SurfaceInteraction makeSurfaceInteraction(const Scene& scene, const Ray& ray, const Hit& hit) {
    SurfaceInteraction si;
    si.geomId = hit.geomId;
    si.primId = hit.primId;
    if (hit.geomId < scene.meshes.size()) {
        const TriangleMesh& mesh = scene.meshes[hit.geomId];
        const uint32_t i0 = mesh.indices[3 * hit.primId], i1 = mesh.indices[3 * hit.primId + 1],
                       i2 = mesh.indices[3 * hit.primId + 2];
        const Vec3f p0 = detail::vertexAt(mesh, i0, ray.time), p1 = detail::vertexAt(mesh, i1, ray.time),
                    p2 = detail::vertexAt(mesh, i2, ray.time);
        const float b1 = hit.u, b2 = hit.v, b0 = 1.0f - b1 - b2;
        si.position = p0 * b0 + p1 * b1 + p2 * b2;
        const Vec3f n = cross(p1 - p0, p2 - p0);
        const float nLength = length(n);
        si.geometricNormal = nLength > 0.0f ? n / nLength : Vec3f{0.0f, 0.0f, 1.0f};
        si.shadingNormal = si.geometricNormal;
        // Vertex normals are only used for meshes that do not deform (they would need keys too).
        if (!mesh.normals.empty() && !mesh.deforms()) {
            const Vec3f ns = mesh.normals[i0] * b0 + mesh.normals[i1] * b1 + mesh.normals[i2] * b2;
            const float nsLength = length(ns);
            if (nsLength > 0.0f) si.shadingNormal = faceForward(ns / nsLength, si.geometricNormal);
        }
        if (!mesh.uvs.empty()) si.uv = mesh.uvs[i0] * b0 + mesh.uvs[i1] * b1 + mesh.uvs[i2] * b2;
        si.material = mesh.material;
        if (mesh.motion.moves()) detail::placeInWorld(mesh.motion.at(ray.time), si);
        if (!(nLength > 0.0f)) si.geometricNormal = si.shadingNormal = normalize(-ray.direction);
    } else {
        const Sphere& sphere = scene.spheres[hit.primId];
        // The hit point, reprojected onto the sphere in the sphere's own space.
        Vec3f hitPoint = ray.at(hit.t);
        Transform toWorld;
        if (sphere.motion.moves()) {
            toWorld = sphere.motion.at(ray.time);
            hitPoint = toWorld.inverse().applyPoint(hitPoint);
        }
        Vec3f outward = hitPoint - sphere.center;
        const float outwardLength = length(outward);
        outward = outwardLength > 0.0f ? outward / outwardLength : Vec3f{0.0f, 0.0f, 1.0f};
        si.position = sphere.center + outward * sphere.radius;
        si.geometricNormal = outward;
        si.shadingNormal = outward;
        const float phi = std::atan2(outward.y, outward.x);
        si.uv = {phi < 0.0f ? phi / (2.0f * kPi) + 1.0f : phi / (2.0f * kPi),
                 std::acos(std::clamp(outward.z, -1.0f, 1.0f)) / kPi};
        si.material = sphere.material;
        if (sphere.motion.moves()) detail::placeInWorld(toWorld, si);
    }
    return si;
}

}  // namespace penumbra
