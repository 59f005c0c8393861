// Our own traversal backend, the second path beside Embree: a 4-wide BVH over the triangles of
// every mesh and the spheres (a binary SAH tree, accel/bvh_build.h, collapsed by
// accel/bvh_wide.h), its four child boxes tested at once with SSE (accel/bvh_box4.h) and
// traversed front to back with a fixed stack; leaves hold blocks of four triangles tested at once
// (accel/bvh_triangle4.h).
// It is meant to agree with Embree hit for hit (tools/crosscheck.h measures how well): the
// triangle test is watertight (geometry/triangle.h; the 4-wide one gives the same results bit
// for bit), the box test conservative, and hits are reported with Embree's conventions
// (accel/traversal.h).
//
// Defined behaviour on bad input: degenerate triangles (zero area) and triangles or spheres with
// non-finite data are left out and never hit; a ray with a NaN or infinite component, a zero
// direction or tnear > tfar hits nothing.
//
// Motion blur, interpolated exactly as Embree is given it and as geometry/surface_interaction.h
// shades it: a deforming mesh's triangles are boxed by the union of their boxes over all keys and
// intersected at Ray::time with vertices from interpolateKeys; a shape with a moving transform is
// an instance, a bottom-level BvhAccelerator over its object-space geometry, boxed in the top level
// conservatively over the whole shutter and intersected with the ray taken into object space by
// motion.at(time).inverse() (the direction is not normalized, so t carries over). These are
// "special" primitives whose global index is past the spheres', so a static scene pays nothing.
//
// Cut-outs (geometry/cut_out.h): the triangles of a mesh with an alpha are special primitives too,
// tested one by one and kept or passed through by keepsCutOutHit, for intersect and occluded
// alike; the ray's hash and, inside an instance, the instance's geomId travel down to the
// instance's tree so that the number is the one Embree's filter computes.
//
// Curves (geometry/curves.h): each segment is one special primitive or, when long for its width,
// up to eight (its dyadic pieces, CurvePiece), boxed by their control points widened by their
// largest radius and tested by intersectCurveSegment, which finds the whole segment's hits.
//
// Bilinear patches (geometry/bilinear_patches.h): each patch is one special primitive, boxed by its
// corners and tested by intersectBilinearPatch, the test Embree's user geometry calls too.
//
// Instancing (SceneGeometry::instances) is the same two-level structure: each prototype mesh gets
// one bottom-level tree, built once, and every instance is a special primitive of the top level,
// boxed by its placement (over the shutter when it moves), that takes the ray into the
// prototype's space and traverses the shared tree; a hit names the instance's geomId and the
// prototype's triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "accel/bvh_build.h"
#include "accel/bvh_wide.h"
#include "accel/traversal.h"
#include "geometry/scene_geometry.h"

namespace penumbra {

struct WatertightRay;
struct WatertightRay4;
class Texture;

class BvhAccelerator {
public:
    explicit BvhAccelerator(const SceneGeometry& scene, const BvhBuildSettings& settings = {});

    // Hits come from the tests geometry/surface_interaction.h's canonicalizeHit uses, bit for bit.
    static constexpr bool kReportsCanonicalHits = true;

    static constexpr std::string_view kName = "bvh";
    static constexpr int kPacketSize = 1;  // no packet kernel
    bool intersect(const Ray& ray, Hit& hit) const;
    bool occluded(const Ray& ray) const;
    // The triangle a ray leaves needs no skipping: the triangle test rejects hits within its own
    // error bound on t of the origin (geometry/triangle.h).
    bool intersect(const Ray& ray, Hit& hit, TriangleLeft) const { return intersect(ray, hit); }
    bool occluded(const Ray& ray, TriangleLeft) const { return occluded(ray); }

    struct Stats {
        size_t nodeCount = 0;  // 4-wide nodes
        size_t leafCount = 0;
        size_t primitiveCount = 0;  // triangles and spheres in the tree
        size_t skippedCount = 0;    // degenerate or non-finite primitives left out
        int maxDepth = 0;           // of the 4-wide tree
        float sahCost = 0.0f;       // of the 4-wide tree, see Bvh4::sahCost
        size_t memoryBytes = 0;     // everything traversal reads: nodes, primitives, id tables
    };
    Stats stats() const;

private:
    // One primitive, 40 bytes: a triangle's three vertices, or a sphere's centre and radius in the
    // first four floats. globalIndex numbers all triangles of all meshes in order, then the
    // spheres, so it is a triangle exactly when it is below triangleCount_.
    struct Primitive {
        float data[9];
        uint32_t globalIndex;
    };
    // Up to four primitives of one leaf, one per lane, laid out for the 4-wide triangle test
    // (accel/bvh_triangle4.h): data[k][lane] is Primitive::data[k]. A leaf of n primitives has
    // ceil(n / 4) blocks, the last one's unused lanes with globalIndex kNoHit; leaves' blocks are
    // in leaf order. Lane `l` of block `b` is primitive 4 b + l.
    struct alignas(32) PrimitiveBlock {
        float data[9][4];
        uint32_t globalIndex[4];
    };
    static Primitive primitiveAt(const PrimitiveBlock& block, int lane);
    // What the cut-out test needs of the traced ray (geometry/cut_out.h): its hash (0 when no
    // tree has a cut-out) and, within an instance's tree, the instance's geomId, which names the
    // hit for the test (kNoInstance at the top level).
    static constexpr uint32_t kNoInstance = ~0u;
    struct CutOutRay {
        uint64_t rayHash = 0;
        uint32_t instanceGeomId = kNoInstance;
    };
    template <bool AnyHit>
    bool intersectLeaf(const Ray& ray, const WatertightRay& triangleRay, const WatertightRay4& triangleRay4,
                       const CutOutRay& cutOutRay, uint32_t firstBlock, uint32_t count, float& tClosest,
                       uint32_t& closest, float& closestB1, float& closestB2, Hit& instanceHit) const;

    void addSpecialPrimitives(const SceneGeometry& scene, const BvhBuildSettings& settings,
                              std::vector<Primitive>& candidates, std::vector<Bounds3f>& bounds);
    template <bool AnyHit>
    bool traverse(const Ray& ray, Hit* hit, const CutOutRay& cutOutRay) const;
    void prefetchChild(const Bvh4Node& node, int i) const;
    void fillHit(const Ray& ray, uint32_t primitive, float t, float b1, float b2, const Hit& specialHit,
                 Hit& hit) const;

    // Deforming triangles, the triangles of still meshes with a cut-out, instances, curve
    // segments and bilinear patches, referenced by globalIndex - specialBase_. A still triangle's vertices
    // are its Primitive's data.
    enum class SpecialKind : uint8_t {
        DeformingTriangle,
        StillTriangle,
        Instance,
        CurveSegment,
        BilinearPatch
    };
    struct Special {
        uint32_t geomId, primId;  // as reported (accel/traversal.h)
        uint32_t source;          // index into deformingMeshes_, instances_, curves_ or patches_
        uint32_t vertex[3];       // a triangle's vertex indices; a curve piece's level and index
        uint32_t cutOut;          // a triangle's index into cutOuts_, or kNoHit: opaque
        SpecialKind kind;
    };
    // The alpha of a mesh with a cut-out and its uvs (geometry/cut_out.h).
    struct CutOut {
        std::shared_ptr<const Texture> alpha;
        std::vector<Vec2f> uvs;
    };
    // Whether a hit at barycentrics (b1, b2) on triangle special `special` is kept by its cut-out.
    bool keepsHit(const Special& special, const CutOutRay& cutOutRay, float b1, float b2) const;
    // A tree placed in the world: by `motion` when it moves, else by `placement`.
    struct Instance {
        MotionTransform motion;
        Transform placement;
        const BvhAccelerator* child;  // object space, never moving; one of children_
    };
    // Intersects instance special `special`, placed by `toWorld` at the ray's time. Out of line:
    // still scenes never call it, and inlined it costs their leaf loop registers.
    template <bool AnyHit>
    [[gnu::noinline]] bool intersectInstance(const Special& special, const Transform& toWorld, const Ray& ray,
                                             const CutOutRay& cutOutRay, float tFar, float& t, float& b1,
                                             float& b2, Hit& instanceHit) const;
    // Intersects special primitive `primitive` within [ray.tnear, tFar]; on a hit (one its cut-out
    // keeps) sets t and, for a triangle, the barycentrics, or for an instance, `instanceHit`.
    template <bool AnyHit>
    bool intersectSpecial(const Ray& ray, const WatertightRay& triangleRay, const CutOutRay& cutOutRay,
                          const Primitive& primitive, float tFar, float& t, float& b1, float& b2,
                          Hit& instanceHit) const;

    Bvh4NodeArray nodes_;
    Bounds3f bounds_;  // of everything in the tree
    std::vector<PrimitiveBlock, HugePageAllocator<PrimitiveBlock, 64>> blocks_;
    size_t primitiveCount_ = 0;
    std::vector<uint32_t> meshFirstTriangle_;  // global index of each mesh's first triangle, then the total
    uint32_t triangleCount_ = 0;
    uint32_t sphereGeomId_ = 0;
    uint32_t specialBase_ = 0;  // triangleCount_ + number of spheres
    std::vector<Special> specials_;
    std::vector<std::vector<std::vector<Vec3f>>> deformingMeshes_;  // position keys
    std::vector<CutOut> cutOuts_;
    std::vector<Curves> curves_;
    std::vector<BilinearPatches> patches_;
    bool hasCutOuts_ = false;  // in this tree or any tree it places
    std::vector<Instance> instances_;
    // The trees instances place: one per moving shape and one per prototype, shared by all its
    // instances.
    std::vector<std::unique_ptr<BvhAccelerator>> children_;
    size_t skippedCount_ = 0;
    size_t leafCount_ = 0;
    int maxDepth_ = 0;
    float sahCost_ = 0.0f;
};

}  // namespace penumbra
static_assert(penumbra::TraversalBackend<penumbra::BvhAccelerator>);
