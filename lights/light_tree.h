// A bounding volume hierarchy over many lights' bounds, by which next-event estimation chooses a
// light at a vertex in time logarithmic in their number: pbrt-v4's BVHLightSampler (Conty Estevez
// and Kulla, "Importance Sampling of Many Lights with Adaptive Tree Splitting", 2018). Each node
// holds the union of its lights' bounds (lights/light_bounds.h); the choice descends from the
// root, at each node to a child with probability proportional to the child's importance at the
// vertex, and a light's probability is the product of its ancestors' choices. The tree is built
// as pbrt-v4 builds it: each node split at the boundary of 12 buckets along an axis that
// minimises power x orientation measure x box area of the two halves.
//
// Where all children's importances are 0 (no light below can light the vertex), the choice goes
// by the children's power instead, so every light of positive power keeps a positive probability
// everywhere (as LightSet's choice among few lights falls back to power); pbrt-v4 returns no
// light there, which would save the shadow ray but not change the estimate.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec.h"
#include "lights/light_bounds.h"

namespace penumbra {

class LightTree {
public:
    // Deep enough for a binary tree built by halving 2^32 lights after kMaxDepthBySurfaceAreaSplit
    // levels of the cost-driven splits (light_tree.cpp).
    static constexpr int kMaxDepth = 64;
    // Children per node: the binary tree's levels collapsed so that one SIMD batch weighs a node's
    // children (bench/README.md, "The light tree").
    static constexpr size_t kWidth = 8;

    LightTree() = default;
    // The tree over lights 0 .. bounds.size() - 1 (`bounds[i]` light i's, its phi the light's power);
    // lights of power 0, or whose bounds are not finite, are left out and never chosen.
    explicit LightTree(const std::vector<LightBounds>& bounds);

    bool empty() const { return nodes_.empty(); }
    size_t nodeCount() const { return nodes_.size(); }
    // Levels of nodes below the root above the deepest light.
    int depth() const { return depth_; }

    struct Choice {
        uint32_t light;
        float probability;
    };
    // A light for the vertex at `p` (surface normal `n`, or a zero vector in a medium), chosen with
    // `u` in [0, 1), which is left as its position within the chosen light's share of [0, 1), so
    // that it can choose again (a point on the light). Not for an empty tree.
    Choice choose(float& u, Vec3f p, Vec3f n) const;
    // The probability that choose() picks `light` at (p, n), the same bits as choose() reports; 0
    // for a light left out.
    float probability(uint32_t light, Vec3f p, Vec3f n) const;

private:
    static constexpr uint32_t kNone = UINT32_MAX;
    static constexpr uint32_t kLightBit = 1u << 31;  // in Node::child: a light, not a node
    struct Node {
        LightBoundsBatchOf<kWidth> children;
        float phi[kWidth] = {};
        uint32_t child[kWidth] = {};  // a node's index, or a light's with kLightBit
        uint32_t childCount = 0;
        uint32_t parent = kNone, slotInParent = 0;
    };
    struct Slot {
        uint32_t node = kNone, slot = 0;
    };
    struct BinaryNode;
    struct Item;
    // The binary tree over items[begin, end) (pbrt-v4's build), its root's index in `binary`.
    static uint32_t buildBinary(std::vector<BinaryNode>& binary, std::vector<Item>& items, size_t begin,
                                size_t end, int depth);
    // The node over the binary subtree at `root`, and below it the nodes over its frontier.
    uint32_t collapse(const std::vector<BinaryNode>& binary, uint32_t root, uint32_t parent, uint32_t slot,
                      int depth);
    // The weights of `node`'s children at (p, n), into w: their importances, or where all are 0
    // their powers. Returns their sum.
    float childWeights(const Node& node, Vec3f p, Vec3f n, float* w) const;

    std::vector<Node> nodes_;
    std::vector<Slot> slotOfLight_;  // node kNone for lights left out
    int depth_ = 0;
};

}  // namespace penumbra
