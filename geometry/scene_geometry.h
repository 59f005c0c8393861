// The shapes of a scene, and the one rule that names them in a backend's hit: mesh i has geomId i
// (primId = its triangle), all spheres share geomId meshes.size() (primId = the sphere), and
// instance k has geomId meshes.size() + 1 + k (primId = the triangle of its prototype, which the
// instance names), curve set c has geomId meshes.size() + 1 + instances.size() + c (primId = its
// segment), and bilinear patch set b the ids after the curves' (primId = its patch). Backends, shading,
// lights and tools ask shapeOf() or the geomId functions below; nothing else spells the rule out.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/bilinear_patches.h"
#include "geometry/curves.h"
#include "geometry/hit.h"
#include "geometry/mesh_instance.h"
#include "geometry/sphere.h"
#include "geometry/triangle_mesh.h"

namespace penumbra {

enum class ShapeKind : uint8_t { Mesh, Sphere, Instance, Curves, BilinearPatches };

// Which shape a hit is on: meshes[index] (triangle `primitive`), spheres[index] (primitive 0) or
// instances[index] (triangle `primitive` of prototypes[instances[index].prototype]) or
// curves[index] (segment `primitive`) or patches[index] (patch `primitive`).
struct ShapeRef {
    ShapeKind kind = ShapeKind::Mesh;
    uint32_t index = 0;
    uint32_t primitive = 0;
    // Whether the primitive is a flat triangle, which a ray leaving it cannot meet again
    // (TriangleLeft); a sphere, a curve or a bilinear patch can be met again.
    bool isTriangle() const { return kind == ShapeKind::Mesh || kind == ShapeKind::Instance; }
};

struct SceneGeometry {
    std::vector<TriangleMesh> meshes;
    std::vector<Sphere> spheres;
    // Meshes defined once and placed by `instances` only; in object space, never moving or
    // deforming, and neither emitting nor naming a material (their instances do).
    std::vector<TriangleMesh> prototypes;
    std::vector<MeshInstance> instances;
    // Never moving; neither emitting nor cut out (the scene loader refuses both).
    std::vector<Curves> curves;
    // Never moving; neither emitting nor cut out (the scene loader refuses both).
    std::vector<BilinearPatches> patches;

    uint32_t meshGeomId(size_t mesh) const { return uint32_t(mesh); }
    uint32_t sphereGeomId() const { return uint32_t(meshes.size()); }
    uint32_t instanceGeomId(size_t instance) const { return uint32_t(meshes.size() + 1 + instance); }
    uint32_t curvesGeomId(size_t curveSet) const { return instanceGeomId(instances.size() + curveSet); }
    uint32_t patchesGeomId(size_t patchSet) const { return curvesGeomId(curves.size() + patchSet); }
    bool isMeshHit(const Hit& hit) const { return hit.geomId < meshes.size(); }

    ShapeRef shapeOf(const Hit& hit) const {
        if (isMeshHit(hit)) return {ShapeKind::Mesh, hit.geomId, hit.primId};
        if (hit.geomId == sphereGeomId()) return {ShapeKind::Sphere, hit.primId, 0};
        const uint32_t firstCurves = curvesGeomId(0);
        if (hit.geomId >= firstCurves) [[unlikely]] {
            const uint32_t firstPatches = patchesGeomId(0);
            if (hit.geomId >= firstPatches)
                return {ShapeKind::BilinearPatches, hit.geomId - firstPatches, hit.primId};
            return {ShapeKind::Curves, hit.geomId - firstCurves, hit.primId};
        }
        return {ShapeKind::Instance, hit.geomId - sphereGeomId() - 1, hit.primId};
    }
    // The hit ids of a shape's primitive (the inverse of shapeOf).
    Hit idsOf(ShapeRef shape) const {
        Hit hit;
        switch (shape.kind) {
            case ShapeKind::Mesh:
                hit.geomId = meshGeomId(shape.index), hit.primId = shape.primitive;
                break;
            case ShapeKind::Sphere:
                hit.geomId = sphereGeomId(), hit.primId = shape.index;
                break;
            case ShapeKind::Instance:
                hit.geomId = instanceGeomId(shape.index), hit.primId = shape.primitive;
                break;
            case ShapeKind::Curves:
                hit.geomId = curvesGeomId(shape.index), hit.primId = shape.primitive;
                break;
            case ShapeKind::BilinearPatches:
                hit.geomId = patchesGeomId(shape.index), hit.primId = shape.primitive;
                break;
        }
        return hit;
    }
    // The triangle mesh a mesh or instance hit lies on (an instance's in object space).
    const TriangleMesh& triangleMeshOf(ShapeRef shape) const {
        return shape.kind == ShapeKind::Instance ? prototypes[instances[shape.index].prototype]
                                                 : meshes[shape.index];
    }
    // Object to world at `time` of a moving mesh or sphere or of any instance (identity otherwise:
    // still meshes, spheres, curves and bilinear patches are in world space).
    Transform toWorldOf(ShapeRef shape, float time) const {
        switch (shape.kind) {
            case ShapeKind::Mesh:
                return meshes[shape.index].motion.at(time);
            case ShapeKind::Sphere:
                return spheres[shape.index].motion.at(time);
            case ShapeKind::Instance:
                return instances[shape.index].toWorld(time);
            case ShapeKind::Curves:
            case ShapeKind::BilinearPatches:
                break;
        }
        return {};
    }
    // The media on the two sides of a shape's surface.
    const MediumInterface& mediaOf(ShapeRef shape) const {
        switch (shape.kind) {
            case ShapeKind::Mesh:
                return meshes[shape.index].media;
            case ShapeKind::Sphere:
                return spheres[shape.index].media;
            case ShapeKind::Curves:
                return curves[shape.index].media;
            case ShapeKind::BilinearPatches:
                return patches[shape.index].media;
            case ShapeKind::Instance:
                break;
        }
        return instances[shape.index].media;
    }
    // Whether the shape's geometry is in a space of its own (toWorldOf is not the identity).
    bool inObjectSpace(ShapeRef shape) const {
        switch (shape.kind) {
            case ShapeKind::Mesh:
                return meshes[shape.index].motion.moves();
            case ShapeKind::Sphere:
                return spheres[shape.index].motion.moves();
            case ShapeKind::Instance:
                return true;
            case ShapeKind::Curves:
            case ShapeKind::BilinearPatches:
                return false;
        }
        return false;
    }

    // Whether any shape moves or deforms over the shutter.
    bool shapesMove() const {
        for (const TriangleMesh& mesh : meshes)
            if (mesh.moves()) return true;
        for (const Sphere& sphere : spheres)
            if (sphere.motion.moves()) return true;
        for (const MeshInstance& instance : instances)
            if (instance.moves()) return true;
        return false;
    }
};

}  // namespace penumbra
