#include "accel/bvh_wide.h"

#include <algorithm>
#include <limits>

namespace penumbra {

namespace {

Bounds3f boundsOf(const BvhNode& node) {
    return {{node.bounds[0], node.bounds[1], node.bounds[2]},
            {node.bounds[3], node.bounds[4], node.bounds[5]}};
}

Bvh4Node emptyNode() {
    Bvh4Node node;
    for (int i = 0; i < kBvhWidth; ++i) {
        for (int plane = 0; plane < 3; ++plane) {
            node.bounds[plane][i] = std::numeric_limits<float>::infinity();
            node.bounds[plane + 3][i] = -std::numeric_limits<float>::infinity();
        }
        node.child[i] = kBvhEmptySlot;
        node.count[i] = 0;
    }
    node.reserved[0] = node.reserved[1] = 0;
    return node;
}

}  // namespace

Bvh4 collapseToBvh4(const BvhBuildResult& binary, const BvhBuildSettings& settings) {
    Bvh4 wide;
    if (binary.nodes.empty()) return wide;
    const BvhNodeArray& in = binary.nodes;
    wide.bounds = boundsOf(in[0]);
    wide.nodes.reserve(in.size() / 2 + 1);
    const float rootArea = wide.bounds.halfArea();
    double cost = 0.0;

    // Depth first.
    struct Pending {
        uint32_t binaryNode;  // an interior node of the binary tree, or the root
        uint32_t wideIndex;   // where its wide node goes
        int depth;
    };
    std::vector<Pending> stack = {{0, 0, 0}};
    wide.nodes.push_back(emptyNode());
    while (!stack.empty()) {
        const Pending p = stack.back();
        stack.pop_back();
        wide.maxDepth = std::max(wide.maxDepth, p.depth);
        cost += double(settings.traversalCost) * double(boundsOf(in[p.binaryNode]).halfArea());

        // Open the interior child of largest area until there are four children or only leaves;
        // an opened child's two children take its place, so the order stays spatial.
        uint32_t children[kBvhWidth];
        int count = 0;
        if (in[p.binaryNode].isLeaf()) {
            children[count++] = p.binaryNode;  // a tree that is a single leaf
        } else {
            children[count++] = in[p.binaryNode].offset;
            children[count++] = in[p.binaryNode].offset + 1;
        }
        while (count < kBvhWidth) {
            int widest = -1;
            float widestArea = -1.0f;
            for (int i = 0; i < count; ++i) {
                if (in[children[i]].isLeaf()) continue;
                const float area = boundsOf(in[children[i]]).halfArea();
                if (area > widestArea) {
                    widest = i;
                    widestArea = area;
                }
            }
            if (widest < 0) break;
            const uint32_t first = in[children[widest]].offset;
            for (int i = count; i > widest + 1; --i) children[i] = children[i - 1];
            children[widest] = first;
            children[widest + 1] = first + 1;
            ++count;
        }

        // A node's interior children are allocated side by side; they are expanded last pushed,
        // first out, so the first child's subtree follows them.
        uint32_t childIndex[kBvhWidth] = {};
        for (int i = 0; i < count; ++i) {
            if (in[children[i]].isLeaf()) continue;
            childIndex[i] = uint32_t(wide.nodes.size());
            wide.nodes.push_back(emptyNode());
        }
        for (int i = count - 1; i >= 0; --i)
            if (!in[children[i]].isLeaf()) stack.push_back({children[i], childIndex[i], p.depth + 1});

        Bvh4Node& node = wide.nodes[p.wideIndex];
        for (int i = 0; i < count; ++i) {
            const BvhNode& c = in[children[i]];
            for (int plane = 0; plane < 6; ++plane) node.bounds[plane][i] = c.bounds[plane];
            if (c.isLeaf()) {
                node.child[i] = c.offset;
                node.count[i] = c.count;
                ++wide.leafCount;
                const int blocks = (c.count + settings.primitivesPerBlock - 1) / settings.primitivesPerBlock;
                cost += double(blocks) * double(boundsOf(c).halfArea());
            } else {
                node.child[i] = childIndex[i];
                node.count[i] = 0;
            }
        }
    }
    wide.sahCost = rootArea > 0.0f ? float(cost / rootArea) : 0.0f;
    wide.nodes.shrink_to_fit();  // the reservation was for the worst case, a binary tree
    return wide;
}

}  // namespace penumbra
