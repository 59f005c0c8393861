#include "scenes/bvh_accelerator.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "scenes/ray_sphere.h"
#include "scenes/ray_triangle.h"

namespace penumbra {

namespace {

constexpr uint32_t kNoHit = std::numeric_limits<uint32_t>::max();

// pbrt-v4's gamma(n) = n u / (1 - n u), u = 2^-24: a bound on the relative error of n rounded
// float operations.
constexpr float gamma(int n) {
    constexpr float u = 0x1p-24f;
    return float(n) * u / (1.0f - float(n) * u);
}
// The slab test's far distances are enlarged by this factor so that rounding can never make a
// ray that touches a box miss it (pbrt-v4, Bounds3::IntersectP; PBR 4th ed. section 6.8.2).
constexpr float kBoxFarScale = 1.0f + 2.0f * gamma(3);

bool isTraceable(const Ray& ray) {
    if (!isFinite(ray.origin) || !isFinite(ray.direction)) return false;
    if (ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) return false;
    return ray.tnear <= ray.tfar;  // false when either is NaN
}

// The ray in the forms the box and triangle tests want, computed once per ray.
struct TraversalRay {
    float origin[3];
    float invDir[3];
    int nearPlane[3], farPlane[3];  // indices into BvhNode::bounds: the slab planes met first and last
    float tnear;
    WatertightRay triangleRay;

    explicit TraversalRay(const Ray& ray) : tnear(ray.tnear), triangleRay(ray.origin, ray.direction) {
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = ray.origin[axis];
            invDir[axis] = 1.0f / ray.direction[axis];  // +-infinity for +-0: the slab comparisons cope
            const bool negative = std::signbit(ray.direction[axis]);
            nearPlane[axis] = negative ? axis + 3 : axis;
            farPlane[axis] = negative ? axis : axis + 3;
        }
    }
};

// Slab test against [tnear, tFar]; tEntry is where the ray enters the box. A NaN slab distance
// (0 * infinity: the origin on a slab plane of an axis the ray does not move along) is skipped by
// the comparisons' order, which keeps the test conservative.
inline bool hitBox(const BvhNode& node, const TraversalRay& r, float tFar, float& tEntry) {
    float t0 = r.tnear, t1 = tFar;
    for (int axis = 0; axis < 3; ++axis) {
        const float slabNear = (node.bounds[r.nearPlane[axis]] - r.origin[axis]) * r.invDir[axis];
        const float slabFar =
            (node.bounds[r.farPlane[axis]] - r.origin[axis]) * r.invDir[axis] * kBoxFarScale;
        t0 = slabNear > t0 ? slabNear : t0;
        t1 = slabFar < t1 ? slabFar : t1;
    }
    tEntry = t0;
    return t0 <= t1;
}

bool isDegenerate(Vec3f p0, Vec3f p1, Vec3f p2) {
    // In double, the edge differences and products of floats are exact or nearly so: a zero
    // cross product means the vertices really are collinear (or coincide).
    const double ax = double(p1.x) - p0.x, ay = double(p1.y) - p0.y, az = double(p1.z) - p0.z;
    const double bx = double(p2.x) - p0.x, by = double(p2.y) - p0.y, bz = double(p2.z) - p0.z;
    return ay * bz - az * by == 0.0 && az * bx - ax * bz == 0.0 && ax * by - ay * bx == 0.0;
}

}  // namespace

BvhAccelerator::BvhAccelerator(const Scene& scene, const BvhBuildSettings& settings) {
    for (const TriangleMesh& mesh : scene.meshes)
        if (mesh.deforms() || mesh.motion.moves())
            throw InputError("the bvh backend does not handle motion blur yet ('" + mesh.name +
                             "' moves); use the embree backend");
    for (const Sphere& sphere : scene.spheres)
        if (sphere.motion.moves())
            throw InputError("the bvh backend does not handle motion blur yet ('" + sphere.name +
                             "' moves); use the embree backend");
    size_t totalTriangles = 0;
    meshFirstTriangle_.reserve(scene.meshes.size() + 1);
    for (const TriangleMesh& mesh : scene.meshes) {
        meshFirstTriangle_.push_back(uint32_t(totalTriangles));
        totalTriangles += mesh.triangleCount();
    }
    meshFirstTriangle_.push_back(uint32_t(totalTriangles));
    if (totalTriangles + scene.spheres.size() >= kNoHit)
        throw std::length_error("BvhAccelerator: more than 2^32 - 1 primitives");
    triangleCount_ = uint32_t(totalTriangles);
    sphereGeomId_ = uint32_t(scene.meshes.size());

    // The primitives that can be hit, with their boxes: which triangles qualify is decided in
    // parallel, then they are packed in order (by a prefix sum) in parallel.
    std::vector<uint8_t> usable(totalTriangles);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, mesh.triangleCount(), 16384),
            [&](const tbb::blocked_range<size_t>& range) {
                for (size_t j = range.begin(); j != range.end(); ++j) {
                    const uint32_t i0 = mesh.indices[3 * j], i1 = mesh.indices[3 * j + 1],
                                   i2 = mesh.indices[3 * j + 2];
                    const size_t n = mesh.positions.size();
                    bool ok = i0 < n && i1 < n && i2 < n;
                    if (ok) {
                        const Vec3f p0 = mesh.positions[i0], p1 = mesh.positions[i1], p2 = mesh.positions[i2];
                        ok = isFinite(p0) && isFinite(p1) && isFinite(p2) && !isDegenerate(p0, p1, p2);
                    }
                    usable[meshFirstTriangle_[m] + j] = ok ? 1 : 0;
                }
            });
    }
    std::vector<uint32_t> packedIndex(totalTriangles);
    size_t usableCount = 0;
    for (size_t g = 0; g < totalTriangles; ++g) {
        packedIndex[g] = uint32_t(usableCount);
        usableCount += usable[g];
    }
    skippedCount_ = totalTriangles - usableCount;
    std::vector<Primitive> candidates(usableCount);
    std::vector<Bounds3f> bounds(usableCount);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, mesh.triangleCount(), 16384),
            [&](const tbb::blocked_range<size_t>& range) {
                for (size_t j = range.begin(); j != range.end(); ++j) {
                    const uint32_t globalIndex = meshFirstTriangle_[m] + uint32_t(j);
                    if (!usable[globalIndex]) continue;
                    const Vec3f p0 = mesh.positions[mesh.indices[3 * j]],
                                p1 = mesh.positions[mesh.indices[3 * j + 1]],
                                p2 = mesh.positions[mesh.indices[3 * j + 2]];
                    const uint32_t k = packedIndex[globalIndex];
                    candidates[k] = {{p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z}, globalIndex};
                    Bounds3f b;
                    b.extend(p0);
                    b.extend(p1);
                    b.extend(p2);
                    bounds[k] = b;
                }
            });
    }
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        const Sphere& sphere = scene.spheres[s];
        if (!isFinite(sphere.center) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f)) {
            ++skippedCount_;
            continue;
        }
        candidates.push_back(
            {{sphere.center.x, sphere.center.y, sphere.center.z, sphere.radius, 0, 0, 0, 0, 0},
             triangleCount_ + uint32_t(s)});
        // center +- radius rounds to nearest; pad by a few ulps so the box surely holds the sphere.
        const float pad = (maxComponent(abs(sphere.center)) + sphere.radius) * 0x1p-20f;
        const Vec3f extent(sphere.radius + pad, sphere.radius + pad, sphere.radius + pad);
        bounds.push_back({sphere.center - extent, sphere.center + extent});
    }

    BvhBuildResult built = buildBvh(bounds, settings);
    nodes_ = std::move(built.nodes);
    maxDepth_ = built.maxDepth;
    sahCost_ = built.sahCost;
    primitives_.resize(candidates.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, candidates.size(), 16384),
                      [&](const tbb::blocked_range<size_t>& range) {
                          for (size_t i = range.begin(); i != range.end(); ++i)
                              primitives_[i] = candidates[built.primitiveOrder[i]];
                      });
}

BvhAccelerator::Stats BvhAccelerator::stats() const {
    Stats s;
    s.nodeCount = nodes_.size();
    for (const BvhNode& node : nodes_) s.leafCount += node.isLeaf() ? 1 : 0;
    s.primitiveCount = primitives_.size();
    s.skippedCount = skippedCount_;
    s.maxDepth = maxDepth_;
    s.sahCost = sahCost_;
    s.memoryBytes = nodes_.capacity() * sizeof(BvhNode) + primitives_.capacity() * sizeof(Primitive) +
                    meshFirstTriangle_.capacity() * sizeof(uint32_t);
    return s;
}

void BvhAccelerator::prefetchBelow(const BvhNode& node) const {
    __builtin_prefetch(node.isLeaf() ? static_cast<const void*>(&primitives_[node.offset])
                                     : static_cast<const void*>(&nodes_[node.offset]));
}

template <bool AnyHit>
bool BvhAccelerator::traverse(const Ray& ray, Hit* hit) const {
    if (nodes_.empty() || !isTraceable(ray)) return false;
    const TraversalRay r(ray);
    const Vec3f origin = ray.origin, direction = ray.direction;

    float tClosest = ray.tfar;
    uint32_t closest = kNoHit;
    float closestB1 = 0.0f, closestB2 = 0.0f;

    // Nodes still to visit, with the distance where the ray enters them: a node entered beyond
    // the closest hit found since it was pushed is skipped. The builder bounds the tree's depth,
    // and at most one node per level is waiting.
    struct Pending {
        uint32_t node;
        float tEntry;
    };
    Pending stack[kBvhMaxDepth];
    int top = 0;

    float tEntry;
    if (!hitBox(nodes_[0], r, tClosest, tEntry)) return false;
    uint32_t current = 0;
    for (;;) {
        const BvhNode& node = nodes_[current];
        if (!node.isLeaf()) {
            const uint32_t first = node.offset, second = node.offset + 1;
            // Incoherent rays wait on memory more than they compute: ask for what each child
            // leads to (its children's pair, or its primitives) before testing the children, so
            // those loads overlap with the box tests and with each other.
            prefetchBelow(nodes_[first]);
            prefetchBelow(nodes_[second]);
            float tFirst, tSecond;
            const bool hitFirst = hitBox(nodes_[first], r, tClosest, tFirst);
            const bool hitSecond = hitBox(nodes_[second], r, tClosest, tSecond);
            if (hitFirst && hitSecond) {
                assert(top < kBvhMaxDepth);
                // Front to back: the nearer child now, the other later.
                if (tSecond < tFirst) {
                    stack[top++] = {first, tFirst};
                    current = second;
                } else {
                    stack[top++] = {second, tSecond};
                    current = first;
                }
                continue;
            }
            if (hitFirst || hitSecond) {
                current = hitFirst ? first : second;
                continue;
            }
        } else {
            for (uint32_t i = node.offset, end = node.offset + node.count; i < end; ++i) {
                const Primitive& p = primitives_[i];
                if (p.globalIndex < triangleCount_) {
                    TriangleHit th;
                    if (!intersectTriangleWatertight(r.triangleRay, p.data, ray.tnear, tClosest, th))
                        continue;
                    if constexpr (AnyHit) return true;
                    tClosest = th.t;
                    closestB1 = th.b1;
                    closestB2 = th.b2;
                    closest = i;
                } else {
                    float t;
                    if (!intersectSphere(origin, direction, {p.data[0], p.data[1], p.data[2]}, p.data[3],
                                         ray.tnear, tClosest, t))
                        continue;
                    if constexpr (AnyHit) return true;
                    tClosest = t;
                    closestB1 = closestB2 = 0.0f;
                    closest = i;
                }
            }
        }
        // Next: the most recently deferred node that may still hold something nearer.
        for (;;) {
            if (top == 0) {
                if (closest == kNoHit) return false;
                if constexpr (!AnyHit) fillHit(ray, closest, tClosest, closestB1, closestB2, *hit);
                return true;
            }
            const Pending& pending = stack[--top];
            if (pending.tEntry <= tClosest) {
                current = pending.node;
                break;
            }
        }
    }
}

void BvhAccelerator::fillHit(const Ray& ray, uint32_t primitive, float t, float b1, float b2,
                             Hit& hit) const {
    const Primitive& p = primitives_[primitive];
    hit.t = t;
    hit.u = b1;
    hit.v = b2;
    if (p.globalIndex < triangleCount_) {
        const Vec3f p0(p.data[0], p.data[1], p.data[2]), p1(p.data[3], p.data[4], p.data[5]),
            p2(p.data[6], p.data[7], p.data[8]);
        hit.geometricNormal = cross(p1 - p0, p2 - p0);
        // The mesh whose range holds the index: the last one starting at or before it.
        const auto next =
            std::upper_bound(meshFirstTriangle_.begin(), meshFirstTriangle_.end(), p.globalIndex);
        const size_t mesh = size_t(next - meshFirstTriangle_.begin()) - 1;
        hit.geomId = uint32_t(mesh);
        hit.primId = p.globalIndex - meshFirstTriangle_[mesh];
    } else {
        // As Embree reports sphere hits: the unnormalized normal is the hit point minus the centre.
        hit.geometricNormal = ray.at(t) - Vec3f(p.data[0], p.data[1], p.data[2]);
        hit.geomId = sphereGeomId_;
        hit.primId = p.globalIndex - triangleCount_;
    }
}

bool BvhAccelerator::intersect(const Ray& ray, Hit& hit) const { return traverse<false>(ray, &hit); }

bool BvhAccelerator::occluded(const Ray& ray) const { return traverse<true>(ray, nullptr); }

}  // namespace penumbra
