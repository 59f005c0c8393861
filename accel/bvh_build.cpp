#include "accel/bvh_build.h"

#include <emmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "core/check.h"
#include "core/simd.h"

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

// A primitive's box in 32 bytes, for SSE: the index rides in the fourth lane of the lower corner.
// Trivial, so that scratch arrays of them are not written before use.
struct alignas(16) BuildRef {
    float lower[3];
    uint32_t index;
    float upper[3];
    float unused;

    __m128 lowerVector() const { return _mm_load_ps(lower); }  // lane 3 holds the index bits: ignore it
    __m128 upperVector() const { return _mm_load_ps(upper); }
    // Twice the centroid: all the binning needs, one multiplication fewer.
    __m128 doubledCentroid() const { return _mm_add_ps(lowerVector(), upperVector()); }
    float doubledCentroid(int axis) const { return lower[axis] + upper[axis]; }
};
static_assert(sizeof(BuildRef) == 32);

// A box as two SSE vectors (lane 3 unused): min and max are one instruction each. Trivial, so
// that bins cost nothing until used; start from Box4::empty().
struct Box4 {
    __m128 lower, upper;

    static Box4 empty() {
        return {_mm_set1_ps(std::numeric_limits<float>::infinity()),
                _mm_set1_ps(-std::numeric_limits<float>::infinity())};
    }

    void extend(__m128 lo, __m128 hi) {
        lower = _mm_min_ps(lower, lo);
        upper = _mm_max_ps(upper, hi);
    }
    void extend(const Box4& b) { extend(b.lower, b.upper); }
    Bounds3f toBounds() const {
        alignas(16) float lo[4], hi[4];
        _mm_store_ps(lo, lower);
        _mm_store_ps(hi, upper);
        return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
    }
    float halfArea() const { return toBounds().halfArea(); }
};

// Maps a (doubled) centroid to one of `count` bins along each axis of the node's centroid bounds.
// Binning and partitioning both call binsOf, so a primitive always lands on the same side.
struct BinMapping {
    int count = kMaxBins;
    float scale[3] = {0.0f, 0.0f, 0.0f};  // 0 along an axis where the centroids do not spread
    __m128 origin4, scale4, lastBin4;

    BinMapping(const Bounds3f& doubledCentroidBounds, int binCount) : count(binCount) {
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = doubledCentroidBounds.upper[axis] - doubledCentroidBounds.lower[axis];
            // Slightly below count / extent so that the largest centroid still lands in the last bin.
            const float s = float(count) * (1.0f - 0x1p-20f) / extent;
            scale[axis] = extent > 0.0f && std::isfinite(s) ? s : 0.0f;
        }
        origin4 = toLanes(doubledCentroidBounds.lower);
        scale4 = toLanes({scale[0], scale[1], scale[2]});
        lastBin4 = _mm_set1_ps(float(count - 1));
    }
    bool canSplit(int axis) const { return scale[axis] > 0.0f; }
    // The bin along each axis (lane 3 is 0).
    __m128i binsOf(const BuildRef& ref) const {
        const __m128 f = _mm_mul_ps(_mm_sub_ps(ref.doubledCentroid(), origin4), scale4);
        return _mm_cvttps_epi32(_mm_max_ps(_mm_min_ps(f, lastBin4), _mm_setzero_ps()));
    }
    int binOf(const BuildRef& ref, int axis) const {
        alignas(16) int32_t bins[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(bins), binsOf(ref));
        return bins[axis];
    }
};

struct Bin {
    Box4 box;
    uint32_t count;
};

struct BinSet {
    int count = 0;
    Bin bins[3][kMaxBins];

    explicit BinSet(int binCount = 0) { reset(binCount); }
    void reset(int binCount) {
        count = binCount;
        for (int axis = 0; axis < 3; ++axis)
            for (int i = 0; i < count; ++i) bins[axis][i] = {Box4::empty(), 0};
    }
    void add(const BuildRef& ref, const BinMapping& mapping) {
        alignas(16) int32_t index[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(index), mapping.binsOf(ref));
        const __m128 lo = ref.lowerVector(), hi = ref.upperVector();
        for (int axis = 0; axis < 3; ++axis) {
            Bin& bin = bins[axis][index[axis]];
            bin.box.extend(lo, hi);
            ++bin.count;
        }
    }
    void merge(const BinSet& other) {
        for (int axis = 0; axis < 3; ++axis)
            for (int i = 0; i < count; ++i) {
                bins[axis][i].box.extend(other.bins[axis][i].box);
                bins[axis][i].count += other.bins[axis][i].count;
            }
    }
};

struct Split {
    int axis = -1;  // -1: no usable split
    int bin = 0;    // primitives in bins [0, bin] go left
    float cost = std::numeric_limits<float>::infinity();
};

// A node's box and the box of its primitives' doubled centroids.
struct NodeExtent {
    Bounds3f bounds;
    Bounds3f doubledCentroidBounds;
};

class Builder {
public:
    Builder(BuildRef* refs, BuildRef* scratch, BvhNode* slots, uint8_t* used,
            const BvhBuildSettings& settings)
        : refs_(refs), scratch_(scratch), slots_(slots), used_(used), settings_(settings) {}

    // Builds the subtree over refs_[begin, end) into the slots [slot, slot + 2 (end - begin) - 1):
    // a subtree over n primitives has at most 2n - 1 nodes, so every subtree knows where its nodes
    // go without asking anyone. Returns the depth of its deepest leaf.
    int build(uint32_t begin, uint32_t end, uint32_t slot, const NodeExtent& extent, int depth) {
        const uint32_t n = end - begin;
        if (n == 1) return writeLeaf(begin, end, slot, extent.bounds, depth);

        Split split;
        BinSet bins;
        const BinMapping mapping(extent.doubledCentroidBounds, binCountFor(n));
        if (depth < kSahDepthLimit) split = findSahSplit(begin, end, extent.bounds, mapping, bins);
        const float leafCost = leafCostOf(n);
        if (n <= uint32_t(settings_.maxLeafSize) && (split.axis < 0 || leafCost <= split.cost))
            return writeLeaf(begin, end, slot, extent.bounds, depth);

        uint32_t mid = begin;
        NodeExtent left, right;
        if (split.axis >= 0) {
            auto goesLeft = [&](const BuildRef& r) { return mapping.binOf(r, split.axis) <= split.bin; };
            if (n >= kParallelBinningSize) {
                mid = partitionInParallel(begin, end, goesLeft);
            } else {
                BuildRef* first = refs_ + begin;
                mid = begin + uint32_t(std::partition(first, refs_ + end, goesLeft) - first);
            }
            left = measure(begin, mid);
            right = measure(mid, end);
        } else {
            // No SAH split: every centroid coincides, or the tree is deep. Split at the median
            // along the axis where centroids spread most; nth_element is deterministic.
            const Vec3f spread = extent.doubledCentroidBounds.upper - extent.doubledCentroidBounds.lower;
            split.axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
            mid = begin + n / 2;
            std::nth_element(refs_ + begin, refs_ + mid, refs_ + end,
                             [axis = split.axis](const BuildRef& a, const BuildRef& b) {
                                 return a.doubledCentroid(axis) < b.doubledCentroid(axis);
                             });
            left = measure(begin, mid);
            right = measure(mid, end);
        }

        PENUMBRA_CHECK(mid > begin && mid < end, "a split leaves primitives on both sides");
        PENUMBRA_CHECK(extent.bounds.contains(left.bounds) && extent.bounds.contains(right.bounds),
                       "a node's box contains its children's boxes");
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

    // The bounds of refs_[begin, end) and of their (doubled) centroids.
    NodeExtent measure(uint32_t begin, uint32_t end) const {
        struct Extent4 {
            Box4 bounds = Box4::empty(), centroids = Box4::empty();
        };
        auto accumulate = [&](const tbb::blocked_range<uint32_t>& range, Extent4 e) {
            for (uint32_t i = range.begin(); i != range.end(); ++i) {
                const __m128 lo = refs_[i].lowerVector(), hi = refs_[i].upperVector();
                e.bounds.extend(lo, hi);
                const __m128 c = _mm_add_ps(lo, hi);
                e.centroids.extend(c, c);
            }
            return e;
        };
        Extent4 e;
        if (end - begin < kParallelBinningSize) {
            e = accumulate({begin, end}, Extent4{});
        } else {
            e = tbb::parallel_reduce(tbb::blocked_range<uint32_t>(begin, end, 16384), Extent4{}, accumulate,
                                     [](Extent4 a, const Extent4& b) {
                                         a.bounds.extend(b.bounds);
                                         a.centroids.extend(b.centroids);
                                         return a;
                                     });
        }
        return {e.bounds.toBounds(), e.centroids.toBounds()};
    }

private:
    // The SAH's cost of testing n primitives, in blocks tested together.
    float leafCostOf(uint32_t n) const {
        const uint32_t block = uint32_t(settings_.primitivesPerBlock);
        return float((n + block - 1) / block);
    }

    // A stable partition in three parallel passes (count per chunk, scatter to the scratch array
    // by prefix sums, copy back): deterministic, and the root's partition is no longer the part
    // of the build that cannot use more cores.
    template <typename Predicate>
    uint32_t partitionInParallel(uint32_t begin, uint32_t end, const Predicate& goesLeft) {
        constexpr uint32_t kChunk = 16384;
        const uint32_t chunks = (end - begin + kChunk - 1) / kChunk;
        auto chunkBegin = [&](uint32_t c) { return begin + c * kChunk; };
        auto chunkEnd = [&](uint32_t c) { return std::min(end, begin + (c + 1) * kChunk); };
        std::vector<uint32_t> leftCount(chunks);
        tbb::parallel_for(uint32_t(0), chunks, [&](uint32_t c) {
            uint32_t count = 0;
            for (uint32_t i = chunkBegin(c); i < chunkEnd(c); ++i) count += goesLeft(refs_[i]) ? 1 : 0;
            leftCount[c] = count;
        });
        std::vector<uint32_t> leftStart(chunks), rightStart(chunks);
        uint32_t totalLeft = 0;
        for (uint32_t c = 0; c < chunks; ++c) totalLeft += leftCount[c];
        for (uint32_t c = 0, left = begin, right = begin + totalLeft; c < chunks; ++c) {
            leftStart[c] = left;
            rightStart[c] = right;
            left += leftCount[c];
            right += (chunkEnd(c) - chunkBegin(c)) - leftCount[c];
        }
        tbb::parallel_for(uint32_t(0), chunks, [&](uint32_t c) {
            uint32_t left = leftStart[c], right = rightStart[c];
            for (uint32_t i = chunkBegin(c); i < chunkEnd(c); ++i)
                scratch_[goesLeft(refs_[i]) ? left++ : right++] = refs_[i];
        });
        tbb::parallel_for(uint32_t(0), chunks, [&](uint32_t c) {
            std::copy(scratch_ + chunkBegin(c), scratch_ + chunkEnd(c), refs_ + chunkBegin(c));
        });
        return begin + totalLeft;
    }

    Split findSahSplit(uint32_t begin, uint32_t end, const Bounds3f& bounds, const BinMapping& mapping,
                       BinSet& bins) const {
        Split best;
        if (!mapping.canSplit(0) && !mapping.canSplit(1) && !mapping.canSplit(2)) return best;
        auto accumulate = [&](const tbb::blocked_range<uint32_t>& range, BinSet set) {
            for (uint32_t i = range.begin(); i != range.end(); ++i) set.add(refs_[i], mapping);
            return set;
        };
        if (end - begin < kParallelBinningSize) {
            // In place: a BinSet is kilobytes, not to be copied for every node.
            bins.reset(mapping.count);
            for (uint32_t i = begin; i != end; ++i) bins.add(refs_[i], mapping);
        } else {
            bins = tbb::parallel_reduce(tbb::blocked_range<uint32_t>(begin, end, 16384),
                                        BinSet(mapping.count), accumulate, [](BinSet a, const BinSet& b) {
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
            Box4 accumulated = Box4::empty();
            uint32_t count = 0;
            for (int i = mapping.count - 1; i > 0; --i) {
                accumulated.extend(axisBins[i].box);
                count += axisBins[i].count;
                rightCost[i - 1] = accumulated.halfArea() * leafCostOf(count);
                rightCount[i - 1] = count;
            }
            accumulated = Box4::empty();
            count = 0;
            for (int i = 0; i < mapping.count - 1; ++i) {
                accumulated.extend(axisBins[i].box);
                count += axisBins[i].count;
                if (count == 0 || rightCount[i] == 0) continue;
                const float cost = settings_.traversalCost +
                                   (accumulated.halfArea() * leafCostOf(count) + rightCost[i]) * invArea;
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
        PENUMBRA_CHECK(end > begin && end - begin <= UINT16_MAX, "a leaf holds 1 to 65535 primitives");
        BvhNode& node = slots_[slot];
        setBounds(node, bounds);
        node.offset = begin;
        node.count = uint16_t(end - begin);
        node.axis = 0;
        node.reserved = 0;
        used_[slot] = 1;
        return depth;
    }
    void writeInterior(uint32_t slot, const Bounds3f& bounds, uint32_t secondChild, int axis) {
        BvhNode& node = slots_[slot];
        setBounds(node, bounds);
        node.offset = secondChild;
        node.count = 0;
        node.axis = uint8_t(axis);
        node.reserved = 0;
        used_[slot] = 1;
    }

    BuildRef* refs_;
    BuildRef* scratch_;  // as large as refs_, for partitions in parallel
    BvhNode* slots_;
    uint8_t* used_;
    const BvhBuildSettings& settings_;
};

}  // namespace

BvhBuildResult buildBvh(const std::vector<Bounds3f>& primitiveBounds, const BvhBuildSettings& settings) {
    BvhBuildResult result;
    const uint32_t n = uint32_t(primitiveBounds.size());
    if (n == 0) return result;

    // Scratch arrays are left uninitialized (their types are trivial): the build writes what it reads.
    const std::unique_ptr<BuildRef[]> refs(new BuildRef[n]);
    const std::unique_ptr<BuildRef[]> scratch(new BuildRef[n]);
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(0, n, 16384), [&](const tbb::blocked_range<uint32_t>& range) {
            for (uint32_t i = range.begin(); i != range.end(); ++i) {
                const Bounds3f& b = primitiveBounds[i];
                refs[i] = {{b.lower.x, b.lower.y, b.lower.z}, i, {b.upper.x, b.upper.y, b.upper.z}, 0.0f};
            }
        });

    // Node slots with holes (2n - 1, the most a tree over n primitives can need), squeezed out below.
    const size_t slotCount = 2 * size_t(n) - 1;
    const std::unique_ptr<BvhNode[]> slots(new BvhNode[slotCount]);
    std::vector<uint8_t> used(slotCount, 0);
    Builder builder(refs.get(), scratch.get(), slots.get(), used.data(), settings);
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
    PENUMBRA_CHECK(result.nodes.size() == count + 1, "every node built is laid out once, after the padding");

    const BvhNode& root = result.nodes[0];
    const float rootArea = Bounds3f{
        {root.bounds[0], root.bounds[1], root.bounds[2]},
        {root.bounds[3], root.bounds[4],
         root.bounds[5]}}.halfArea();
    double cost = 0.0;
    for (size_t i = 0; i < result.nodes.size(); ++i) {
        if (i == 1) continue;  // padding
        const BvhNode& node = result.nodes[i];
        PENUMBRA_CHECK(
            node.isLeaf() ? size_t(node.offset) + node.count <= n
                          : node.offset % 2 == 0 && node.offset > i && node.offset + 1 < result.nodes.size(),
            "a leaf's primitives lie in the primitive order; an interior node's children are a pair "
            "after it");
        const float area = Bounds3f{
            {node.bounds[0], node.bounds[1], node.bounds[2]},
            {node.bounds[3], node.bounds[4],
             node.bounds[5]}}.halfArea();
        const double blocks =
            double((node.count + settings.primitivesPerBlock - 1) / settings.primitivesPerBlock);
        cost += double(area) * (node.isLeaf() ? blocks : double(settings.traversalCost));
    }
    result.sahCost = rootArea > 0.0f ? float(cost / rootArea) : 0.0f;

    result.primitiveOrder.resize(n);
    for (uint32_t i = 0; i < n; ++i) result.primitiveOrder[i] = refs[i].index;
    return result;
}

}  // namespace penumbra
