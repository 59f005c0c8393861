// The 4-wide BVH that our traversal backend walks (accel/bvh_accelerator.h), made by collapsing
// the binary SAH tree of accel/bvh_build.h: each node takes up to four children, found by
// repeatedly opening the child with the largest surface area, as in Wald, Benthin and Boulos,
// "Getting Rid of Packets: Efficient SIMD Single-Ray Traversal using Multi-branching BVHs"
// (IEEE Symposium on Interactive Ray Tracing, 2008) and Embree. A 4-wide node has a third as many
// levels as a binary tree, and its four child boxes are tested at once with SSE
// (accel/bvh_box4.h): incoherent rays wait on one memory access per level.
//
// The collapse is sequential and depends only on the binary tree, so the wide tree does not
// depend on the number of threads either.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "accel/bvh_build.h"
#include "core/huge_page_allocator.h"

namespace penumbra {

inline constexpr int kBvhWidth = 4;

// One node in 128 bytes (two cache lines), its four child boxes in structure-of-arrays form so
// that one SSE load fetches a slab plane of all four. A child is an interior node (count 0, `child`
// its node index), a leaf (count > 0, `child` its first primitive in leaf order) or an empty slot
// (an empty box, lower +inf and upper -inf, which no ray meets; count 0, child kBvhEmptySlot).
struct alignas(64) Bvh4Node {
    float bounds[6][kBvhWidth];  // [plane][child]; planes as BvhNode::bounds: lower x, y, z, upper x, y, z
    uint32_t child[kBvhWidth];
    uint16_t count[kBvhWidth];
    uint32_t reserved[2];

    bool isLeaf(int i) const { return count[i] > 0; }
    Bounds3f childBounds(int i) const {
        return {{bounds[0][i], bounds[1][i], bounds[2][i]}, {bounds[3][i], bounds[4][i], bounds[5][i]}};
    }
};
static_assert(sizeof(Bvh4Node) == 128, "4-wide BVH nodes are meant to be two cache lines");

inline constexpr uint32_t kBvhEmptySlot = 0xffffffffu;

using Bvh4NodeArray = std::vector<Bvh4Node, HugePageAllocator<Bvh4Node, 64>>;

struct Bvh4 {
    Bvh4NodeArray nodes;  // nodes[0] is the root; a node's interior children are side by side; empty
                          // when there are no primitives
    Bounds3f bounds;      // the root's box
    size_t leafCount = 0;
    int maxDepth = 0;  // of the wide tree, root at depth 0; never more than the binary tree's
    // The SAH cost of the wide tree, in units of one block test per ray that meets the root box,
    // with one 4-wide node test costing the settings' traversalCost (see BvhBuildSettings).
    float sahCost = 0.0f;
};

// Collapses a binary tree (its primitive order carries over unchanged). A binary tree that is a
// single leaf becomes a root with one leaf child.
Bvh4 collapseToBvh4(const BvhBuildResult& binary, const BvhBuildSettings& settings = {});

}  // namespace penumbra
