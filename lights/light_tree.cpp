#include "lights/light_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/check.h"

namespace penumbra {

namespace {

// Cost-driven splits down to this depth; below it, halving by count bounds the depth
// (kMaxDepth) and the recursion whatever the lights' layout.
constexpr int kMaxDepthBySurfaceAreaSplit = 32;
constexpr int kBuckets = 12;
constexpr float kNodeNearestDistanceFraction = 0.5f;  // of the node's radius (importanceOf)
constexpr float kOneMinusUlp = 0x1.fffffep-1f;        // the largest float below 1

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
    leafOfLight_.assign(bounds.size(), kNone);
    if (items.empty()) return;
    nodes_.reserve(2 * items.size() - 1);
    build(items, 0, items.size(), kNone, 0);
}

uint32_t LightTree::build(std::vector<Item>& items, size_t begin, size_t end, uint32_t parent, int depth) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back(Node{});
    nodes_[index].parent = parent;
    depth_ = std::max(depth_, depth);
    if (end - begin == 1) {
        nodes_[index].bounds = items[begin].bounds;
        nodes_[index].isLeaf = true;
        nodes_[index].secondChildOrLight = items[begin].light;
        leafOfLight_[items[begin].light] = index;
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
    build(items, begin, middle, index, depth + 1);
    const uint32_t second = build(items, middle, end, index, depth + 1);
    nodes_[index].secondChildOrLight = second;
    nodes_[index].bounds = unionOf(nodes_[index + 1].bounds, nodes_[second].bounds);
    return index;
}

float LightTree::importanceOf(uint32_t node, Vec3f p, Vec3f n) const {
    const LightBounds& b = nodes_[node].bounds;
    // A light's own distance clamp is its radius (lights/light_bounds.h); a node's a half of its
    // radius: a point inside a node's sphere usually lies nearer than the radius to some of its
    // lights, and the larger clamp took that away from the nodes beside it (bench/README.md, "The
    // light tree", measured).
    const float nearest = nodes_[node].isLeaf ? b.radius : kNodeNearestDistanceFraction * b.radius;
    return b.importance(p, n, nearest * nearest);
}

float LightTree::firstChildProbability(uint32_t node, Vec3f p, Vec3f n) const {
    const LightBounds& first = nodes_[node + 1].bounds;
    const LightBounds& second = nodes_[nodes_[node].secondChildOrLight].bounds;
    float w0 = importanceOf(node + 1, p, n), w1 = importanceOf(nodes_[node].secondChildOrLight, p, n);
    if (!(w0 + w1 > 0.0f)) {
        w0 = first.phi;
        w1 = second.phi;
    }
    const float p0 = w0 / (w0 + w1);
    return p0 >= 0.0f && p0 <= 1.0f ? p0 : 0.5f;  // infinite powers: halves
}

LightTree::Choice LightTree::choose(float& u, Vec3f p, Vec3f n) const {
    PENUMBRA_CHECK(!nodes_.empty(), "a light tree chooses among some lights");
    uint32_t node = 0;
    float probability = 1.0f;
    while (!nodes_[node].isLeaf) {
        const float p0 = firstChildProbability(node, p, n);
        if (u < p0) {
            u = std::min(u / p0, kOneMinusUlp);
            probability *= p0;
            node = node + 1;
        } else {
            u = std::clamp((u - p0) / (1.0f - p0), 0.0f, kOneMinusUlp);
            probability *= 1.0f - p0;
            node = nodes_[node].secondChildOrLight;
        }
    }
    return {nodes_[node].secondChildOrLight, probability};
}

float LightTree::probability(uint32_t light, Vec3f p, Vec3f n) const {
    if (light >= leafOfLight_.size() || leafOfLight_[light] == kNone) return 0.0f;
    // The choices from the leaf up, then multiplied from the root down as choose() does.
    std::array<float, kMaxDepth + 1> factors;
    int count = 0;
    for (uint32_t node = leafOfLight_[light]; nodes_[node].parent != kNone; node = nodes_[node].parent) {
        const uint32_t parent = nodes_[node].parent;
        const float p0 = firstChildProbability(parent, p, n);
        factors[size_t(count++)] = node == parent + 1 ? p0 : 1.0f - p0;
    }
    float probability = 1.0f;
    while (count > 0) probability *= factors[size_t(--count)];
    return probability;
}

}  // namespace penumbra
