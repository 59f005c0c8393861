// The bounding volume hierarchy of our own traversal backend (accel/bvh_accelerator.h) and its
// builder: a binned surface-area-heuristic (SAH) build in the manner of Wald, "On fast Construction
// of SAH-based Bounding Volume Hierarchies" (IEEE Symposium on Interactive Ray Tracing, 2007),
// parallel over subtrees with TBB. The result depends only on the input, never on the number of
// threads or on scheduling: every subtree owns a fixed range of primitives and of node slots.
// Traversal walks this tree collapsed into a 4-wide one (accel/bvh_wide.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/huge_page_allocator.h"
#include "core/vec.h"

namespace penumbra {

// An axis-aligned box; the default is empty (lower > upper) and absorbs whatever is added to it.
struct Bounds3f {
    Vec3f lower{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                std::numeric_limits<float>::infinity()};
    Vec3f upper{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                -std::numeric_limits<float>::infinity()};

    void extend(Vec3f p) {
        lower = min(lower, p);
        upper = max(upper, p);
    }
    void extend(const Bounds3f& b) {
        lower = min(lower, b.lower);
        upper = max(upper, b.upper);
    }
    bool isEmpty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
    // Whether `b` lies within this box (a NaN coordinate counts as within: only order is tested).
    bool contains(const Bounds3f& b) const {
        return !(b.lower.x < lower.x || b.lower.y < lower.y || b.lower.z < lower.z || b.upper.x > upper.x ||
                 b.upper.y > upper.y || b.upper.z > upper.z);
    }
    Vec3f centroid() const { return (lower + upper) * 0.5f; }
    // Half the surface area: the SAH only uses ratios of areas.
    float halfArea() const {
        if (isEmpty()) return 0.0f;
        const Vec3f d = upper - lower;
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

// One node in 32 bytes. The two children of an interior node are siblings in the array, at
// `offset` and `offset + 1`, and every such pair starts on a 64-byte boundary, so both children's
// boxes arrive in one cache line (the collapse into 4-wide nodes, bvh_wide.h, reads them together). Pairs are
// laid out depth first (a subtree's pairs follow its root's). A leaf's primitives are [offset, offset +
// count) of the primitive order. The root is node 0; node 1 is padding. Trivial on purpose (no member
// initializers), so the builder's scratch arrays of nodes are not written before use; BvhNode{} is all zeros.
struct alignas(32) BvhNode {
    float bounds[6];   // lower x, y, z, then upper x, y, z
    uint32_t offset;   // interior: index of the first child; leaf: first primitive
    uint16_t count;    // primitives in a leaf; 0 marks an interior node
    uint8_t axis;      // split axis of an interior node
    uint8_t reserved;  // room for flags (e.g. motion-blurred subtrees)

    bool isLeaf() const { return count > 0; }
};
static_assert(sizeof(BvhNode) == 32, "BVH nodes are meant to be 32 bytes");

// Cache-line aligned (a sibling pair shares a line); large arrays on huge pages.
using BvhNodeArray = std::vector<BvhNode, HugePageAllocator<BvhNode, 64>>;

struct BvhBuildSettings {
    // Two blocks of four: fewer levels to wait on, and the SAH still picks smaller leaves where
    // they pay (measured on the bunny and the dragon, bench/README.md).
    int maxLeafSize = 8;
    // Primitives tested together in a leaf: a leaf of n primitives costs ceil(n / primitivesPerBlock)
    // block tests (as in Embree's builders; ours tests four triangles at once, bvh_triangle4.h).
    int primitivesPerBlock = 4;
    // SAH costs, relative to one block test: a leaf costs its blocks, an interior node
    // traversalCost + (area-weighted children). Testing a node's child boxes costs about as much
    // as testing a block of triangles.
    float traversalCost = 1.0f;
};

struct BvhBuildResult {
    BvhNodeArray nodes;                    // nodes[0] is the root; empty when there are no primitives
    std::vector<uint32_t> primitiveOrder;  // leaf order -> index into the input bounds
    int maxDepth = 0;                      // root is depth 0
    // Expected cost of a random ray that meets the root box, by the SAH with the build's costs,
    // in units of one block test: a measure of tree quality.
    float sahCost = 0.0f;
};

// The tree is at most this deep (root at depth 0), so traversal fits a fixed stack of this size.
inline constexpr int kBvhMaxDepth = 64;

// Builds over the given primitive boxes (each one non-empty and finite).
BvhBuildResult buildBvh(const std::vector<Bounds3f>& primitiveBounds, const BvhBuildSettings& settings = {});

}  // namespace penumbra
