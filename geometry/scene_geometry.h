// The shapes of a scene, and the one rule that names them in a backend's hit: mesh i has geomId i
// (primId = its triangle), and all spheres share geomId meshes.size() (primId = the sphere).
// Backends, shading, lights and tools ask shapeOf() or the geomId functions below; nothing else
// spells the rule out.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/hit.h"
#include "geometry/sphere.h"
#include "geometry/triangle_mesh.h"

namespace penumbra {

enum class ShapeKind : uint8_t { Mesh, Sphere };

// Which shape a hit is on: meshes[index] (triangle `primitive`) or spheres[index] (primitive 0).
struct ShapeRef {
    ShapeKind kind = ShapeKind::Mesh;
    uint32_t index = 0;
    uint32_t primitive = 0;
};

struct SceneGeometry {
    std::vector<TriangleMesh> meshes;
    std::vector<Sphere> spheres;

    uint32_t meshGeomId(size_t mesh) const { return uint32_t(mesh); }
    uint32_t sphereGeomId() const { return uint32_t(meshes.size()); }
    bool isMeshHit(const Hit& hit) const { return hit.geomId < meshes.size(); }

    ShapeRef shapeOf(const Hit& hit) const {
        if (isMeshHit(hit)) return {ShapeKind::Mesh, hit.geomId, hit.primId};
        return {ShapeKind::Sphere, hit.primId, 0};
    }
    // The hit ids of a shape's primitive (the inverse of shapeOf).
    Hit idsOf(ShapeRef shape) const {
        Hit hit;
        hit.geomId = shape.kind == ShapeKind::Mesh ? meshGeomId(shape.index) : sphereGeomId();
        hit.primId = shape.kind == ShapeKind::Mesh ? shape.primitive : shape.index;
        return hit;
    }
    const MotionTransform& motionOf(ShapeRef shape) const {
        return shape.kind == ShapeKind::Mesh ? meshes[shape.index].motion : spheres[shape.index].motion;
    }

    // Whether any shape moves or deforms over the shutter.
    bool shapesMove() const {
        for (const TriangleMesh& mesh : meshes)
            if (mesh.moves()) return true;
        for (const Sphere& sphere : spheres)
            if (sphere.motion.moves()) return true;
        return false;
    }
};

}  // namespace penumbra
