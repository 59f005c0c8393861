#include "lights/light_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/check.h"
#include "core/discrete_distribution.h"

namespace penumbra {

namespace {

// Cost-driven splits down to this depth; below it, halving by count bounds the depth
// (kMaxDepth) and the recursion whatever the lights' layout.
constexpr int kMaxDepthBySurfaceAreaSplit = 32;
constexpr int kBuckets = 12;
constexpr float kNodeNearestDistanceFraction = 0.5f;  // of the node's radius (collapse)

struct Box {
    Vec3f lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
             std::numeric_limits<float>::max()};
    Vec3f hi{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
             -std::numeric_limits<float>::max()};
    void grow(const Box& b) {
        lo = min(lo, b.lo);
        hi = max(hi, b.hi);
    }
    void grow(Vec3f p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    bool isEmpty() const { return lo.x > hi.x; }
    float surfaceArea() const {
        if (isEmpty()) return 0.0f;
        const Vec3f d = hi - lo;
        return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
};

// The solid-angle measure of the directions a cone of normals (half-angle theta_o) emits into
// with an emission angle theta_e beyond it (pbrt-v4's LightBounds cost, after Conty Estevez and
// Kulla 2018, eq. 1).
float orientationMeasure(const LightBounds& b) {
    constexpr float kPi = std::numbers::pi_v<float>;
    const float thetaO = std::acos(std::clamp(b.cosThetaO, -1.0f, 1.0f));
    const float thetaE = std::acos(std::clamp(b.cosThetaE, -1.0f, 1.0f));
    const float thetaW = std::min(thetaO + thetaE, kPi);
    const float sinThetaO = std::sin(thetaO);
    return 2.0f * kPi * (1.0f - b.cosThetaO) +
           kPi / 2.0f *
               (2.0f * thetaW * sinThetaO - std::cos(thetaO - 2.0f * thetaW) - 2.0f * thetaO * sinThetaO +
                b.cosThetaO);
}

// The cost of a node with these bounds: power x orientation measure x box area, the area scaled
// by how elongated the parent's box is along the split axis (pbrt-v4's Kr), so that long boxes
// split across their length.
float nodeCost(const LightBounds& b, const Box& box, float elongation) {
    return elongation * b.phi * orientationMeasure(b) * box.surfaceArea();
}

bool isFinite(const LightBounds& b) {
    return std::isfinite(b.center.x) && std::isfinite(b.center.y) && std::isfinite(b.center.z) &&
           std::isfinite(b.radius) && std::isfinite(b.phi) && std::isfinite(b.axis.x) &&
           std::isfinite(b.axis.y) && std::isfinite(b.axis.z);
}

}  // namespace

struct LightTree::Item {
    LightBounds bounds;
    Box box;  // the bounding sphere's box
    Vec3f centroid;
    uint32_t light;
};

struct LightTree::BinaryNode {
    LightBounds bounds;
    uint32_t secondChildOrLight = 0;  // the first child is the next node
    bool isLeaf = false;
};

LightTree::LightTree(const std::vector<LightBounds>& bounds) {
    std::vector<Item> items;
    for (size_t i = 0; i < bounds.size(); ++i) {
        const LightBounds& b = bounds[i];
        if (!(b.phi > 0.0f) || !isFinite(b)) continue;
        Item item{b, {}, b.center, uint32_t(i)};
        const Vec3f r(b.radius, b.radius, b.radius);
        item.box.grow(b.center - r);
        item.box.grow(b.center + r);
        items.push_back(item);
    }
    PENUMBRA_CHECK(bounds.size() < kLightBit, "light indices leave kLightBit free");
    slotOfLight_.assign(bounds.size(), Slot{});
    if (items.empty()) return;
    std::vector<BinaryNode> binary;
    binary.reserve(2 * items.size() - 1);
    buildBinary(binary, items, 0, items.size(), 0);
    collapse(binary, 0, kNone, 0, 0);
}

uint32_t LightTree::buildBinary(std::vector<BinaryNode>& binary, std::vector<Item>& items, size_t begin,
                                size_t end, int depth) {
    const uint32_t index = uint32_t(binary.size());
    binary.push_back(BinaryNode{});
    if (end - begin == 1) {
        binary[index].bounds = items[begin].bounds;
        binary[index].isLeaf = true;
        binary[index].secondChildOrLight = items[begin].light;
        return index;
    }
    Box box, centroids;
    for (size_t i = begin; i < end; ++i) {
        box.grow(items[i].box);
        centroids.grow(items[i].centroid);
    }
    // The split: the bucket boundary of least cost over the three axes (pbrt-v4's), or halving by
    // count where no boundary separates the lights or the tree is deep.
    size_t middle = begin + (end - begin) / 2;
    int bestAxis = -1, bestBoundary = 0;
    const auto bucketOf = [&](const Item& item, int axis) {
        const float extent = centroids.hi[axis] - centroids.lo[axis];
        const float f = float(kBuckets) * (item.centroid[axis] - centroids.lo[axis]) / extent;
        return f >= 0.0f ? std::min(int(f), kBuckets - 1) : 0;  // NaN: bucket 0
    };
    if (depth < kMaxDepthBySurfaceAreaSplit) {
        const Vec3f diagonal = box.hi - box.lo;
        float bestCost = std::numeric_limits<float>::infinity();
        for (int axis = 0; axis < 3; ++axis) {
            if (!(centroids.hi[axis] > centroids.lo[axis])) continue;
            std::array<LightBounds, kBuckets> bucketBounds{};
            std::array<Box, kBuckets> bucketBoxes{};
            for (size_t i = begin; i < end; ++i) {
                const int bucket = bucketOf(items[i], axis);
                bucketBounds[size_t(bucket)] = unionOf(bucketBounds[size_t(bucket)], items[i].bounds);
                bucketBoxes[size_t(bucket)].grow(items[i].box);
            }
            const float elongation = maxComponent(diagonal) / std::max(diagonal[axis], 1e-30f);
            for (int boundary = 1; boundary < kBuckets; ++boundary) {
                LightBounds below{}, above{};
                Box belowBox, aboveBox;
                for (int b = 0; b < boundary; ++b) {
                    below = unionOf(below, bucketBounds[size_t(b)]);
                    belowBox.grow(bucketBoxes[size_t(b)]);
                }
                for (int b = boundary; b < kBuckets; ++b) {
                    above = unionOf(above, bucketBounds[size_t(b)]);
                    aboveBox.grow(bucketBoxes[size_t(b)]);
                }
                if (!(below.phi > 0.0f) || !(above.phi > 0.0f)) continue;
                const float cost =
                    nodeCost(below, belowBox, elongation) + nodeCost(above, aboveBox, elongation);
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestBoundary = boundary;
                }
            }
        }
    }
    if (bestAxis >= 0) {
        const Item* split = std::partition(items.data() + begin, items.data() + end, [&](const Item& item) {
            return bucketOf(item, bestAxis) < bestBoundary;
        });
        middle = size_t(split - items.data());
    }
    if (middle == begin || middle == end) middle = begin + (end - begin) / 2;
    if (bestAxis < 0) {
        // Halving: by the centroids along the box's longest axis, so that halves stay compact.
        const Vec3f extent = centroids.hi - centroids.lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        std::nth_element(items.begin() + ptrdiff_t(begin), items.begin() + ptrdiff_t(middle),
                         items.begin() + ptrdiff_t(end), [axis](const Item& a, const Item& b) {
                             return a.centroid[axis] < b.centroid[axis];
                         });
    }
    buildBinary(binary, items, begin, middle, depth + 1);
    const uint32_t second = buildBinary(binary, items, middle, end, depth + 1);
    binary[index].secondChildOrLight = second;
    binary[index].bounds = unionOf(binary[index + 1].bounds, binary[second].bounds);
    return index;
}

uint32_t LightTree::collapse(const std::vector<BinaryNode>& binary, uint32_t root, uint32_t parent,
                             uint32_t slot, int depth) {
    // The frontier: the binary root's children (or the root, a lone light), the one of most power
    // among them replaced by its two children until kWidth of them.
    std::vector<uint32_t> frontier;
    if (binary[root].isLeaf)
        frontier = {root};
    else
        frontier = {root + 1, binary[root].secondChildOrLight};
    while (frontier.size() < kWidth) {
        size_t widest = frontier.size();
        for (size_t k = 0; k < frontier.size(); ++k)
            if (!binary[frontier[k]].isLeaf &&
                (widest == frontier.size() ||
                 binary[frontier[k]].bounds.phi > binary[frontier[widest]].bounds.phi))
                widest = k;
        if (widest == frontier.size()) break;  // all lights
        const uint32_t expanded = frontier[widest];
        frontier[widest] = expanded + 1;
        frontier.insert(frontier.begin() + ptrdiff_t(widest) + 1, binary[expanded].secondChildOrLight);
    }
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.emplace_back();
    depth_ = std::max(depth_, depth);
    nodes_[index].parent = parent;
    nodes_[index].slotInParent = slot;
    nodes_[index].childCount = uint32_t(frontier.size());
    for (uint32_t k = 0; k < frontier.size(); ++k) {
        const BinaryNode& b = binary[frontier[k]];
        nodes_[index].phi[k] = b.bounds.phi;
        if (b.isLeaf) {
            // A light's own distance clamp is its radius (lights/light_bounds.h).
            nodes_[index].children.set(k, b.bounds);
            nodes_[index].child[k] = b.secondChildOrLight | kLightBit;
            slotOfLight_[b.secondChildOrLight] = {index, k};
        } else {
            // A node's is half its radius: a point inside a node's sphere usually lies nearer than
            // the radius to some of its lights, and the larger clamp took that away from the nodes
            // beside it (bench/README.md, "The light tree", measured).
            const float nearest = kNodeNearestDistanceFraction * b.bounds.radius;
            nodes_[index].children.set(k, b.bounds, nearest * nearest);
            const uint32_t child = collapse(binary, frontier[k], index, k, depth + 1);
            nodes_[index].child[k] = child;
        }
    }
    return index;
}

float LightTree::childWeights(const Node& node, Vec3f p, Vec3f n, float* w) const {
    node.children.importances(p, n, w);
    float total = 0.0f;
    for (uint32_t k = 0; k < node.childCount; ++k) total += w[k];
    if (total > 0.0f && std::isfinite(total)) return total;
    // No light below can light the point (or powers overflow): by power, which keeps every
    // light's probability positive.
    total = 0.0f;
    for (uint32_t k = 0; k < node.childCount; ++k) total += w[k] = node.phi[k];
    return total;
}

LightTree::Choice LightTree::choose(float& u, Vec3f p, Vec3f n) const {
    PENUMBRA_CHECK(!nodes_.empty(), "a light tree chooses among some lights");
    float probability = 1.0f;
    for (uint32_t node = 0;;) {
        const Node& current = nodes_[node];
        alignas(32) float w[kWidth];
        const float total = childWeights(current, p, n, w);
        // The child whose interval of [0, total) holds u * total; u then becomes the position
        // within it (as LightSet::chooseLocally).
        const float target = u * total;
        uint32_t chosen = 0;
        float chosenStart = 0.0f, start = 0.0f;
        for (uint32_t k = 0; k < current.childCount; ++k) {
            if (w[k] > 0.0f) {  // a child of weight 0 is never chosen, even through rounding
                chosen = k;
                chosenStart = start;
                if (target < start + w[k]) break;
            }
            start += w[k];
        }
        u = std::clamp((target - chosenStart) / w[chosen], 0.0f, DiscreteDistribution::kOneMinusUlp);
        probability *= w[chosen] / total;
        const uint32_t child = current.child[chosen];
        if (child & kLightBit) return {child & ~kLightBit, probability};
        node = child;
    }
}

float LightTree::probability(uint32_t light, Vec3f p, Vec3f n) const {
    if (light >= slotOfLight_.size() || slotOfLight_[light].node == kNone) return 0.0f;
    // The choices from the light up, then multiplied from the root down as choose() does.
    std::array<float, kMaxDepth + 1> factors;
    int count = 0;
    for (Slot at = slotOfLight_[light]; at.node != kNone;
         at = {nodes_[at.node].parent, nodes_[at.node].slotInParent}) {
        alignas(32) float w[kWidth];
        const float total = childWeights(nodes_[at.node], p, n, w);
        factors[size_t(count++)] = w[at.slot] / total;
    }
    float probability = 1.0f;
    while (count > 0) probability *= factors[size_t(--count)];
    return probability;
}

}  // namespace penumbra
