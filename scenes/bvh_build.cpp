#include "scenes/bvh_build.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

namespace penumbra {

namespace {

// At most this many bins per axis; small nodes use fewer (cheaper, and as good there).
constexpr int kMaxBins = 32;
// Subtrees with at least this many primitives are built as separate TBB tasks.
constexpr uint32_t kParallelSubtreeSize = 4096;
// Nodes with at least this many primitives are binned by a parallel reduction. Bin contents are
// counts, minima and maxima, which combine exactly in any order, so the result is deterministic.
constexpr uint32_t kParallelBinningSize = 65536;
// Below this depth splits are by the median, which halves the primitive count at every level:
// with at most 2^32 primitives the tree stays within kBvhMaxDepth levels whatever the input.
constexpr int kSahDepthLimit = kBvhMaxDepth - 33;

int binCountFor(uint32_t primitives) { return primitives <= 16 ? 8 : (primitives <= 256 ? 16 : kMaxBins); }

struct BuildRef {
    float lower[3], upper[3];
    float centroid[3];
    uint32_t index = 0;
};

// Maps a centroid to one of `count` bins along each axis of the node's centroid bounds.
struct BinMapping {
    int count = kMaxBins;
    float origin[3] = {0.0f, 0.0f, 0.0f};
    float scale[3] = {0.0f, 0.0f, 0.0f};  // 0 along an axis where the centroids do not spread

    BinMapping(const Bounds3f& centroidBounds, int binCount) : count(binCount) {
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = centroidBounds.lower[axis];
            const float extent = centroidBounds.upper[axis] - centroidBounds.lower[axis];
            // Slightly below count / extent so that the largest centroid still lands in the last bin.
            const float s = float(count) * (1.0f - 0x1p-20f) / extent;
            scale[axis] = extent > 0.0f && std::isfinite(s) ? s : 0.0f;
        }
    }
    bool canSplit(int axis) const { return scale[axis] > 0.0f; }
    int binOf(const BuildRef& ref, int axis) const {
        const float f = (ref.centroid[axis] - origin[axis]) * scale[axis];
        return std::clamp(int(std::min(f, float(count - 1))), 0, count - 1);
    }
};

struct Bin {
    float lower[3], upper[3];
    uint32_t count;

    void clear() {
        for (int k = 0; k < 3; ++k) {
            lower[k] = std::numeric_limits<float>::infinity();
            upper[k] = -std::numeric_limits<float>::infinity();
        }
        count = 0;
    }
    Bounds3f bounds() const { return {{lower[0], lower[1], lower[2]}, {upper[0], upper[1], upper[2]}}; }
};

struct BinSet {
    int count = 0;
    Bin bins[3][kMaxBins];

    explicit BinSet(int binCount = 0) : count(binCount) {
        for (int axis = 0; axis < 3; ++axis)
            for (int i = 0; i < count; ++i) bins[axis][i].clear();
    }
    void add(const BuildRef& ref, const BinMapping& mapping) {
        for (int axis = 0; axis < 3; ++axis) {
            if (!mapping.canSplit(axis)) continue;
            Bin& bin = bins[axis][mapping.binOf(ref, axis)];
            for (int k = 0; k < 3; ++k) {
                bin.lower[k] = std::min(bin.lower[k], ref.lower[k]);
                bin.upper[k] = std::max(bin.upper[k], ref.upper[k]);
            }
            ++bin.count;
        }
    }
    void merge(const BinSet& other) {
        for (int axis = 0; axis < 3; ++axis)
            for (int i = 0; i < count; ++i) {
                Bin& bin = bins[axis][i];
                const Bin& o = other.bins[axis][i];
                for (int k = 0; k < 3; ++k) {
                    bin.lower[k] = std::min(bin.lower[k], o.lower[k]);
                    bin.upper[k] = std::max(bin.upper[k], o.upper[k]);
                }
                bin.count += o.count;
            }
    }
};

struct Split {
    int axis = -1;  // -1: no usable split
    int bin = 0;    // primitives in bins [0, bin] go left
    float cost = std::numeric_limits<float>::infinity();
};

struct NodeExtent {
    Bounds3f bounds;
    Bounds3f centroidBounds;
};

class Builder {
public:
    Builder(std::vector<BuildRef>& refs, std::vector<BvhNode>& slots, std::vector<uint8_t>& used,
            const BvhBuildSettings& settings)
        : refs_(refs), slots_(slots), used_(used), settings_(settings) {}

    // Builds the subtree over refs_[begin, end) into the slots [slot, slot + 2 (end - begin) - 1):
    // a subtree over n primitives has at most 2n - 1 nodes, so every subtree knows where its nodes
    // go without asking anyone. Returns the depth of its deepest leaf.
    int build(uint32_t begin, uint32_t end, uint32_t slot, const NodeExtent& extent, int depth) {
        const uint32_t n = end - begin;
        if (n == 1) return writeLeaf(begin, end, slot, extent.bounds, depth);

        Split split;
        BinSet bins;
        const BinMapping mapping(extent.centroidBounds, binCountFor(n));
        if (depth < kSahDepthLimit) split = findSahSplit(begin, end, extent.bounds, mapping, bins);
        const float leafCost = float(n);
        if (n <= uint32_t(settings_.maxLeafSize) && (split.axis < 0 || leafCost <= split.cost))
            return writeLeaf(begin, end, slot, extent.bounds, depth);

        uint32_t mid = begin;
        NodeExtent left, right;
        if (split.axis >= 0) {
            BuildRef* first = refs_.data() + begin;
            BuildRef* middle = std::partition(first, refs_.data() + end, [&](const BuildRef& r) {
                return mapping.binOf(r, split.axis) <= split.bin;
            });
            mid = begin + uint32_t(middle - first);
            left = measure(begin, mid);
            right = measure(mid, end);
        } else {
            // No SAH split: every centroid coincides, or the tree is deep. Split at the median
            // along the axis where centroids spread most; nth_element is deterministic.
            const Vec3f spread = extent.centroidBounds.upper - extent.centroidBounds.lower;
            split.axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
            mid = begin + n / 2;
            std::nth_element(refs_.data() + begin, refs_.data() + mid, refs_.data() + end,
                             [axis = split.axis](const BuildRef& a, const BuildRef& b) {
                                 return a.centroid[axis] < b.centroid[axis];
                             });
            left = measure(begin, mid);
            right = measure(mid, end);
        }

        const uint32_t leftSlot = slot + 1;
        const uint32_t rightSlot = slot + 2 * (mid - begin);
        writeInterior(slot, extent.bounds, rightSlot, split.axis);
        int leftDepth = 0, rightDepth = 0;
        if (n >= kParallelSubtreeSize) {
            tbb::parallel_invoke([&] { leftDepth = build(begin, mid, leftSlot, left, depth + 1); },
                                 [&] { rightDepth = build(mid, end, rightSlot, right, depth + 1); });
        } else {
            leftDepth = build(begin, mid, leftSlot, left, depth + 1);
            rightDepth = build(mid, end, rightSlot, right, depth + 1);
        }
        return std::max(leftDepth, rightDepth);
    }

    // The bounds of refs_[begin, end) and of their centroids.
    NodeExtent measure(uint32_t begin, uint32_t end) const {
        auto accumulate = [&](const tbb::blocked_range<uint32_t>& range, NodeExtent e) {
            float lower[3], upper[3], cLower[3], cUpper[3];
            for (int k = 0; k < 3; ++k) {
                lower[k] = e.bounds.lower[k];
                upper[k] = e.bounds.upper[k];
                cLower[k] = e.centroidBounds.lower[k];
                cUpper[k] = e.centroidBounds.upper[k];
            }
            for (uint32_t i = range.begin(); i != range.end(); ++i) {
                const BuildRef& r = refs_[i];
                for (int k = 0; k < 3; ++k) {
                    lower[k] = std::min(lower[k], r.lower[k]);
                    upper[k] = std::max(upper[k], r.upper[k]);
                    cLower[k] = std::min(cLower[k], r.centroid[k]);
                    cUpper[k] = std::max(cUpper[k], r.centroid[k]);
                }
            }
            e.bounds = {{lower[0], lower[1], lower[2]}, {upper[0], upper[1], upper[2]}};
            e.centroidBounds = {{cLower[0], cLower[1], cLower[2]}, {cUpper[0], cUpper[1], cUpper[2]}};
            return e;
        };
        if (end - begin < kParallelBinningSize) return accumulate({begin, end}, NodeExtent{});
        return tbb::parallel_reduce(
            tbb::blocked_range<uint32_t>(begin, end, 16384), NodeExtent{}, accumulate,
            [](NodeExtent a, const NodeExtent& b) {
                a.bounds.extend(b.bounds);
                a.centroidBounds.extend(b.centroidBounds);
                return a;
            });
    }

private:
    Split findSahSplit(uint32_t begin, uint32_t end, const Bounds3f& bounds, const BinMapping& mapping,
                       BinSet& bins) const {
        Split best;
        if (!mapping.canSplit(0) && !mapping.canSplit(1) && !mapping.canSplit(2)) return best;
        auto accumulate = [&](const tbb::blocked_range<uint32_t>& range, BinSet set) {
            for (uint32_t i = range.begin(); i != range.end(); ++i) set.add(refs_[i], mapping);
            return set;
        };
        if (end - begin < kParallelBinningSize) {
            bins = accumulate({begin, end}, BinSet(mapping.count));
        } else {
            bins = tbb::parallel_reduce(tbb::blocked_range<uint32_t>(begin, end, 16384), BinSet(mapping.count),
                                        accumulate,
                                        [](BinSet a, const BinSet& b) {
                                            a.merge(b);
                                            return a;
                                        });
        }

        const float area = bounds.halfArea();
        const float invArea = area > 0.0f ? 1.0f / area : 0.0f;
        for (int axis = 0; axis < 3; ++axis) {
            if (!mapping.canSplit(axis)) continue;
            const auto& axisBins = bins.bins[axis];
            // Right-hand sides of every split, swept from the right; split i puts bins [0, i] left.
            float rightCost[kMaxBins] = {};
            uint32_t rightCount[kMaxBins] = {};
            Bounds3f accumulated;
            uint32_t count = 0;
            for (int i = mapping.count - 1; i > 0; --i) {
                accumulated.extend(axisBins[i].bounds());
                count += axisBins[i].count;
                rightCost[i - 1] = accumulated.halfArea() * float(count);
                rightCount[i - 1] = count;
            }
            accumulated = Bounds3f{};
            count = 0;
            for (int i = 0; i < mapping.count - 1; ++i) {
                accumulated.extend(axisBins[i].bounds());
                count += axisBins[i].count;
                if (count == 0 || rightCount[i] == 0) continue;
                const float cost =
                    settings_.traversalCost + (accumulated.halfArea() * float(count) + rightCost[i]) * invArea;
                if (cost < best.cost) best = {axis, i, cost};
            }
        }
        return best;
    }

    static void setBounds(BvhNode& node, const Bounds3f& b) {
        node.bounds[0] = b.lower.x;
        node.bounds[1] = b.lower.y;
        node.bounds[2] = b.lower.z;
        node.bounds[3] = b.upper.x;
        node.bounds[4] = b.upper.y;
        node.bounds[5] = b.upper.z;
    }
    int writeLeaf(uint32_t begin, uint32_t end, uint32_t slot, const Bounds3f& bounds, int depth) {
        BvhNode& node = slots_[slot];
        setBounds(node, bounds);
        node.offset = begin;
        node.count = uint16_t(end - begin);
        node.axis = 0;
        used_[slot] = 1;
        return depth;
    }
    void writeInterior(uint32_t slot, const Bounds3f& bounds, uint32_t secondChild, int axis) {
        BvhNode& node = slots_[slot];
        setBounds(node, bounds);
        node.offset = secondChild;
        node.count = 0;
        node.axis = uint8_t(axis);
        used_[slot] = 1;
    }

    std::vector<BuildRef>& refs_;
    std::vector<BvhNode>& slots_;
    std::vector<uint8_t>& used_;
    const BvhBuildSettings& settings_;
};

}  // namespace

BvhBuildResult buildBvh(const std::vector<Bounds3f>& primitiveBounds, const BvhBuildSettings& settings) {
    BvhBuildResult result;
    const uint32_t n = uint32_t(primitiveBounds.size());
    if (n == 0) return result;

    std::vector<BuildRef> refs(n);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 16384), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t i = range.begin(); i != range.end(); ++i) {
            const Bounds3f& b = primitiveBounds[i];
            const Vec3f c = b.centroid();
            refs[i] = {{b.lower.x, b.lower.y, b.lower.z}, {b.upper.x, b.upper.y, b.upper.z}, {c.x, c.y, c.z}, i};
        }
    });

    // Node slots with holes (2n - 1, the most a tree over n primitives can need), squeezed out below.
    std::vector<BvhNode> slots(2 * size_t(n) - 1);
    std::vector<uint8_t> used(slots.size(), 0);
    Builder builder(refs, slots, used, settings);
    result.maxDepth = builder.build(0, n, 0, builder.measure(0, n), 0);

    // Lay the nodes out again with siblings side by side, each pair on a cache line of its own.
    // Slots were written depth first with the first child right after its parent and the second
    // child's slot in `offset`.
    size_t count = 0;
    for (uint8_t u : used) count += u;
    result.nodes.reserve(count + 1);
    result.nodes.push_back(slots[0]);
    result.nodes.push_back(BvhNode{});  // padding: pairs start at even indices
    struct Placement {
        uint32_t slot, index;  // a node's slot, and its place in the final array
    };
    std::vector<Placement> pending = {{0, 0}};
    while (!pending.empty()) {
        const Placement p = pending.back();
        pending.pop_back();
        const BvhNode& node = slots[p.slot];
        if (node.isLeaf()) continue;
        const uint32_t firstSlot = p.slot + 1, secondSlot = node.offset;
        const uint32_t pair = uint32_t(result.nodes.size());
        result.nodes.push_back(slots[firstSlot]);
        result.nodes.push_back(slots[secondSlot]);
        result.nodes[p.index].offset = pair;
        // Second child pushed first, so the first child's subtree is laid out first.
        pending.push_back({secondSlot, pair + 1});
        pending.push_back({firstSlot, pair});
    }

    const BvhNode& root = result.nodes[0];
    const float rootArea = Bounds3f{{root.bounds[0], root.bounds[1], root.bounds[2]},
                                    {root.bounds[3], root.bounds[4], root.bounds[5]}}
                               .halfArea();
    double cost = 0.0;
    for (size_t i = 0; i < result.nodes.size(); ++i) {
        if (i == 1) continue;  // padding
        const BvhNode& node = result.nodes[i];
        const float area = Bounds3f{{node.bounds[0], node.bounds[1], node.bounds[2]},
                                    {node.bounds[3], node.bounds[4], node.bounds[5]}}
                               .halfArea();
        cost += double(area) * (node.isLeaf() ? double(node.count) : double(settings.traversalCost));
    }
    result.sahCost = rootArea > 0.0f ? float(cost / rootArea) : 0.0f;

    result.primitiveOrder.resize(n);
    for (uint32_t i = 0; i < n; ++i) result.primitiveOrder[i] = refs[i].index;
    return result;
}

}  // namespace penumbra
