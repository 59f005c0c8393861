// Our own traversal backend, the second path beside Embree: a binary BVH over the triangles of
// every mesh and the spheres (scenes/bvh_build.h), traversed front to back with a fixed stack.
// It is meant to agree with Embree hit for hit (tools/crosscheck.h measures how well): the
// triangle test is watertight (scenes/ray_triangle.h), the box test conservative, and hits are
// reported with Embree's conventions (accelerator.h).
//
// Defined behaviour on bad input: degenerate triangles (zero area) and triangles or spheres with
// non-finite data are left out and never hit; a ray with a NaN or infinite component, a zero
// direction or tnear > tfar hits nothing.
//
// Motion blur is not handled yet: a scene where something moves is refused with an InputError,
// and Ray::time is ignored. Room is left for it: primitives are referenced by a global index
// (their vertex keys can live beside the static data), and nodes have a spare byte for flags such
// as "this subtree moves".
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scenes/accelerator.h"
#include "scenes/bvh_build.h"

namespace penumbra {

class BvhAccelerator final : public Accelerator {
public:
    explicit BvhAccelerator(const Scene& scene, const BvhBuildSettings& settings = {});

    std::string_view name() const override { return "bvh"; }
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;

    struct Stats {
        size_t nodeCount = 0;
        size_t leafCount = 0;
        size_t primitiveCount = 0;  // triangles and spheres in the tree
        size_t skippedCount = 0;    // degenerate or non-finite primitives left out
        int maxDepth = 0;
        float sahCost = 0.0f;    // see BvhBuildResult::sahCost
        size_t memoryBytes = 0;  // everything traversal reads: nodes, primitives, id tables
    };
    Stats stats() const;

private:
    // One primitive in leaf order, 40 bytes: a triangle's three vertices, or a sphere's centre and
    // radius in the first four floats. globalIndex numbers all triangles of all meshes in order,
    // then the spheres, so it is a triangle exactly when it is below triangleCount_.
    struct Primitive {
        float data[9];
        uint32_t globalIndex;
    };

    template <bool AnyHit>
    bool traverse(const Ray& ray, Hit* hit) const;
    void prefetchBelow(const BvhNode& node) const;
    void fillHit(const Ray& ray, uint32_t primitive, float t, float b1, float b2, Hit& hit) const;

    BvhNodeArray nodes_;
    std::vector<Primitive> primitives_;
    std::vector<uint32_t> meshFirstTriangle_;  // global index of each mesh's first triangle, then the total
    uint32_t triangleCount_ = 0;
    uint32_t sphereGeomId_ = 0;
    size_t skippedCount_ = 0;
    int maxDepth_ = 0;
    float sahCost_ = 0.0f;
};

}  // namespace penumbra
