#include "accel/bvh_accelerator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <utility>

#include "accel/bvh_box4.h"
#include "accel/bvh_triangle4.h"
#include "core/check.h"
#include "core/error.h"
#include "geometry/cut_out.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace penumbra {

namespace {

constexpr uint32_t kNoHit = std::numeric_limits<uint32_t>::max();

bool isTraceable(const Ray& ray) {
    if (!isFinite(ray.origin) || !isFinite(ray.direction) || !std::isfinite(ray.time)) return false;
    if (ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) return false;
    return ray.tnear <= ray.tfar;  // false when either is NaN
}

// Whether a mesh's triangles are special primitives, tested one by one: when it moves, deforms or
// has a cut-out.
bool isSpecialMesh(const TriangleMesh& mesh) { return mesh.deforms() || mesh.motion.moves() || mesh.alpha; }

bool isDegenerate(Vec3f p0, Vec3f p1, Vec3f p2) {
    // In double, the edge differences and products of floats are exact or nearly so: a zero
    // cross product means the vertices really are collinear (or coincide).
    const double ax = double(p1.x) - p0.x, ay = double(p1.y) - p0.y, az = double(p1.z) - p0.z;
    const double bx = double(p2.x) - p0.x, by = double(p2.y) - p0.y, bz = double(p2.z) - p0.z;
    return ay * bz - az * by == 0.0 && az * bx - ax * bz == 0.0 && ax * by - ay * bx == 0.0;
}

// A box padded on every side by `pad` plus a few ulps of its largest coordinate.
Bounds3f padded(const Bounds3f& b, float pad) {
    const float scale = std::max(maxComponent(abs(b.lower)), maxComponent(abs(b.upper)));
    const float p = pad + scale * 0x1p-18f;
    return {b.lower - Vec3f(p, p, p), b.upper + Vec3f(p, p, p)};
}

// A world box holding `objectBox` under `motion` at every time of the shutter. Each key segment is
// sampled at kSamples + 1 evenly spaced fractions (the transformed corners bound the transformed
// box, the transform being affine), and the result is padded by how far any object point can move
// between samples: within a segment a point p moves at most |dT| + theta * max|S| |p| + max|dS| |p|
// per unit of the segment fraction, theta being the slerp's rotation angle.
Bounds3f boundsOverShutter(const MotionTransform& motion, const Bounds3f& objectBox) {
    constexpr int kSamples = 64;
    Vec3f corners[8];
    float radius = 0.0f;
    for (int c = 0; c < 8; ++c) {
        corners[c] = {(c & 1) ? objectBox.upper.x : objectBox.lower.x,
                      (c & 2) ? objectBox.upper.y : objectBox.lower.y,
                      (c & 4) ? objectBox.upper.z : objectBox.lower.z};
        radius = std::max(radius, length(corners[c]));
    }
    Bounds3f result;
    float pad = 0.0f;
    const size_t segments = motion.keys.size() - 1;
    for (size_t seg = 0; seg < segments; ++seg) {
        const TransformKey& a = motion.keys[seg];
        const TransformKey& b = motion.keys[seg + 1];
        const float norms = std::sqrt(a.rotation.dot(a.rotation) * b.rotation.dot(b.rotation));
        const float cosHalf =
            norms > 0.0f ? std::min(std::abs(a.rotation.dot(b.rotation)) / norms, 1.0f) : 0.0f;
        // 2 acos(cos) is the rotation angle; a margin covers the normalized lerp of close keys
        // and rounding.
        const float theta = 2.0f * std::acos(cosHalf) * 1.05f + 1e-4f;
        const float maxScale = std::max(maxComponent(abs(a.scale)), maxComponent(abs(b.scale)));
        const float scaleChange = maxComponent(abs(b.scale - a.scale));
        const float speed =
            length(b.translation - a.translation) + theta * maxScale * radius + scaleChange * radius;
        pad = std::max(pad, speed / float(kSamples));  // twice the half spacing, for safety
        for (int i = 0; i <= kSamples; ++i) {
            const float time = (float(seg) + float(i) / float(kSamples)) / float(segments);
            const Transform toWorld = motion.at(time);
            for (const Vec3f& c : corners) result.extend(toWorld.applyPoint(c));
        }
    }
    return padded(result, pad);
}

// A world box holding `objectBox` placed by `toWorld`: its transformed corners (the transform
// being affine), padded for their rounding.
Bounds3f placedBounds(const Transform& toWorld, const Bounds3f& objectBox) {
    Bounds3f result;
    for (int c = 0; c < 8; ++c)
        result.extend(toWorld.applyPoint({(c & 1) ? objectBox.upper.x : objectBox.lower.x,
                                          (c & 2) ? objectBox.upper.y : objectBox.lower.y,
                                          (c & 4) ? objectBox.upper.z : objectBox.lower.z}));
    return padded(result, 0.0f);
}

// The box of piece `index` of 2^level of a Bezier segment with control points p and radii r: a
// Bezier lies in its control points' hull and its radius is at most its largest control radius.
// Padded for the rounding by which the test's own halving, in the ray's space, may differ.
Bounds3f curvePieceBox(const Vec3f* p, const float* r, uint32_t level, uint32_t index) {
    Vec3f points[4] = {p[0], p[1], p[2], p[3]};
    float radii[4] = {r[0], r[1], r[2], r[3]};
    for (int k = int(level) - 1; k >= 0; --k) {
        Vec3f left[4], right[4];
        float leftRadii[4], rightRadii[4];
        curve::split(points, left, right);
        curve::split(radii, leftRadii, rightRadii);
        const bool second = ((index >> k) & 1u) != 0;
        for (int i = 0; i < 4; ++i) {
            points[i] = second ? right[i] : left[i];
            radii[i] = second ? rightRadii[i] : leftRadii[i];
        }
    }
    Bounds3f box;
    float radius = 0.0f;
    for (int i = 0; i < 4; ++i) {
        box.extend(points[i]);
        radius = std::max(radius, radii[i]);
    }
    const float magnitude = std::max(maxComponent(abs(box.lower)), maxComponent(abs(box.upper)));
    const float pad = radius * 1.001f + magnitude * 1e-6f;
    const Vec3f extent(pad, pad, pad);
    return padded({box.lower - extent, box.upper + extent}, 0.0f);
}

}  // namespace

BvhAccelerator::BvhAccelerator(const SceneGeometry& scene, const BvhBuildSettings& settings) {
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
    sphereGeomId_ = scene.sphereGeomId();

    // The primitives that can be hit, with their boxes: which triangles qualify is decided in
    // parallel, then they are packed in order (by a prefix sum) in parallel.
    std::vector<uint8_t> usable(totalTriangles, 0);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (isSpecialMesh(mesh)) continue;  // special primitives, below
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
    size_t specialTriangles = 0;
    for (const TriangleMesh& mesh : scene.meshes)
        if (isSpecialMesh(mesh)) specialTriangles += mesh.triangleCount();
    skippedCount_ = totalTriangles - specialTriangles - usableCount;
    std::vector<Primitive> candidates(usableCount);
    std::vector<Bounds3f> bounds(usableCount);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, mesh.triangleCount(), 16384),
            [&](const tbb::blocked_range<size_t>& range) {
                for (size_t j = range.begin(); j != range.end(); ++j) {
                    const uint32_t globalIndex = meshFirstTriangle_[m] + uint32_t(j);
                    if (!usable[globalIndex]) continue;  // also every triangle of a special mesh
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
        if (sphere.motion.moves()) continue;  // an instance, below
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

    specialBase_ = triangleCount_ + uint32_t(scene.spheres.size());
    addSpecialPrimitives(scene, settings, candidates, bounds);

    const BvhBuildResult built = buildBvh(bounds, settings);
    Bvh4 wide = collapseToBvh4(built, settings);
    nodes_ = std::move(wide.nodes);
    bounds_ = wide.bounds;
    leafCount_ = wide.leafCount;
    maxDepth_ = wide.maxDepth;
    sahCost_ = wide.sahCost;
    primitiveCount_ = candidates.size();

    // Each leaf's primitives into blocks of four; the leaf then names its first block.
    struct Leaf {
        uint32_t first, count, firstBlock;  // first: in the builder's primitive order
    };
    std::vector<Leaf> leaves;
    leaves.reserve(leafCount_);
    uint64_t blockCount = 0;
    for (Bvh4Node& node : nodes_)
        for (int i = 0; i < kBvhWidth; ++i) {
            if (!node.isLeaf(i)) continue;
            leaves.push_back({node.child[i], node.count[i], uint32_t(blockCount)});
            node.child[i] = uint32_t(blockCount);
            blockCount += (node.count[i] + 3) / 4;
        }
    if (uint64_t(blockCount) * 4 >= kNoHit)
        throw std::length_error("BvhAccelerator: too many primitive blocks");
    blocks_.resize(blockCount);
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, leaves.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t l = range.begin(); l != range.end(); ++l) {
                const Leaf& leaf = leaves[l];
                for (uint32_t k = 0; k < (leaf.count + 3) / 4 * 4; ++k) {
                    PrimitiveBlock& block = blocks_[leaf.firstBlock + k / 4];
                    const Primitive p = k < leaf.count ? candidates[built.primitiveOrder[leaf.first + k]]
                                                       : Primitive{{0, 0, 0, 0, 0, 0, 0, 0, 0}, kNoHit};
                    for (int j = 0; j < 9; ++j) block.data[j][k % 4] = p.data[j];
                    block.globalIndex[k % 4] = p.globalIndex;
                }
            }
        });
}

BvhAccelerator::Primitive BvhAccelerator::primitiveAt(const PrimitiveBlock& block, int lane) {
    Primitive p;
    for (int j = 0; j < 9; ++j) p.data[j] = block.data[j][lane];
    p.globalIndex = block.globalIndex[lane];
    return p;
}

void BvhAccelerator::addSpecialPrimitives(const SceneGeometry& scene, const BvhBuildSettings& settings,
                                          std::vector<Primitive>& candidates, std::vector<Bounds3f>& bounds) {
    // `data`: a still triangle's vertices.
    auto addSpecial = [&](const Special& special, const Bounds3f& box, const Primitive& data = {}) {
        if (uint64_t(specialBase_) + specials_.size() >= kNoHit)
            throw std::length_error("BvhAccelerator: more than 2^32 - 1 primitives");
        Primitive candidate = data;
        candidate.globalIndex = specialBase_ + uint32_t(specials_.size());
        candidates.push_back(candidate);
        bounds.push_back(box);
        specials_.push_back(special);
    };
    // The cut-out of `mesh`, when it has one: its index into cutOuts_.
    auto cutOutOf = [&](const TriangleMesh& mesh) {
        if (!mesh.alpha) return kNoHit;
        cutOuts_.push_back({mesh.alpha, mesh.uvs});
        hasCutOuts_ = true;
        return uint32_t(cutOuts_.size() - 1);
    };
    // An instance of tree `child` (object space), placed by `motion` when it moves, else by
    // `placement`, and boxed in the world over the whole shutter.
    auto placeInstance = [&](const BvhAccelerator* child, const MotionTransform& motion,
                             const Transform& placement, uint32_t geomId, uint32_t primId) {
        if (child->nodes_.empty()) return;
        const Bounds3f worldBox = motion.moves() ? boundsOverShutter(motion, child->bounds_)
                                                 : placedBounds(placement, child->bounds_);
        if (!isFinite(worldBox.lower) || !isFinite(worldBox.upper)) {
            ++skippedCount_;
            return;
        }
        Special special{};
        special.geomId = geomId;
        special.primId = primId;
        special.source = uint32_t(instances_.size());
        special.cutOut = kNoHit;
        special.kind = SpecialKind::Instance;
        hasCutOuts_ = hasCutOuts_ || child->hasCutOuts_;
        instances_.push_back({motion, placement, child});
        addSpecial(special, worldBox);
    };
    // A moving shape: the shape alone, in object space, in a tree of its own.
    auto addInstance = [&](SceneGeometry&& child, const MotionTransform& motion, uint32_t geomId,
                           uint32_t primId) {
        auto accelerator = std::make_unique<BvhAccelerator>(child, settings);
        skippedCount_ += accelerator->skippedCount_;
        children_.push_back(std::move(accelerator));
        placeInstance(children_.back().get(), motion, Transform(), geomId, primId);
    };
    // A still mesh with a cut-out: each usable triangle (as the constructor decides for the others)
    // a special primitive holding its vertices.
    auto addStillCutOutMesh = [&](const TriangleMesh& mesh, uint32_t geomId, uint32_t cutOut) {
        const size_t n = mesh.positions.size();
        for (size_t j = 0; j < mesh.triangleCount(); ++j) {
            Special special{};
            special.geomId = geomId;
            special.primId = uint32_t(j);
            special.cutOut = cutOut;
            special.kind = SpecialKind::StillTriangle;
            bool ok = true;
            for (int k = 0; k < 3; ++k) {
                special.vertex[k] = mesh.indices[3 * j + k];
                ok = ok && special.vertex[k] < n;
            }
            Vec3f p[3];
            for (int k = 0; ok && k < 3; ++k) {
                p[k] = mesh.positions[special.vertex[k]];
                ok = isFinite(p[k]);
            }
            if (!ok || isDegenerate(p[0], p[1], p[2])) {
                ++skippedCount_;
                continue;
            }
            Bounds3f box;
            for (const Vec3f& v : p) box.extend(v);
            addSpecial(
                special, box,
                Primitive{{p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y, p[2].z}, 0});
        }
    };
    // The scene's instances: one tree per prototype (its positions and indices only), traversed
    // by every instance that places it (pbrt-v4's TransformedPrimitive over a shared BVHAggregate).
    std::vector<const BvhAccelerator*> prototypeTrees;
    for (const TriangleMesh& prototype : scene.prototypes) {
        SceneGeometry child;
        child.meshes.emplace_back();
        child.meshes[0].positions = prototype.positions;
        child.meshes[0].indices = prototype.indices;
        if (prototype.alpha) {
            child.meshes[0].alpha = prototype.alpha;
            child.meshes[0].uvs = prototype.uvs;
        }
        auto accelerator = std::make_unique<BvhAccelerator>(child, settings);
        skippedCount_ += accelerator->skippedCount_;
        children_.push_back(std::move(accelerator));
        prototypeTrees.push_back(children_.back().get());
    }
    for (size_t k = 0; k < scene.instances.size(); ++k) {
        const MeshInstance& instance = scene.instances[k];
        placeInstance(prototypeTrees[instance.prototype], instance.motion, instance.placement,
                      scene.instanceGeomId(k), kNoHit);
    }
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (mesh.motion.moves()) {
            SceneGeometry child;
            child.meshes.push_back(mesh);
            child.meshes[0].motion.keys.clear();
            child.meshes[0].normals.clear();
            if (!mesh.alpha) child.meshes[0].uvs.clear();
            addInstance(std::move(child), mesh.motion, scene.meshGeomId(m), kNoHit);
            continue;
        }
        if (!mesh.deforms()) {
            if (mesh.alpha) addStillCutOutMesh(mesh, scene.meshGeomId(m), cutOutOf(mesh));
            continue;
        }
        const uint32_t source = uint32_t(deformingMeshes_.size());
        deformingMeshes_.push_back(mesh.positionKeys);
        const uint32_t cutOut = cutOutOf(mesh);
        size_t vertexCount = mesh.positions.size();
        for (const auto& key : mesh.positionKeys) vertexCount = std::min(vertexCount, key.size());
        for (size_t j = 0; j < mesh.triangleCount(); ++j) {
            Special special{};
            special.geomId = scene.meshGeomId(m);
            special.primId = uint32_t(j);
            special.source = source;
            special.cutOut = cutOut;
            special.kind = SpecialKind::DeformingTriangle;
            bool ok = true;
            Bounds3f box;
            for (int k = 0; k < 3; ++k) {
                special.vertex[k] = mesh.indices[3 * j + k];
                ok = ok && special.vertex[k] < vertexCount;
            }
            // Linear interpolation keeps every point of the triangle inside the union of its boxes
            // at the keys (up to rounding, which the padding covers).
            for (size_t key = 0; ok && key < mesh.positionKeys.size(); ++key)
                for (int k = 0; k < 3; ++k) {
                    const Vec3f p = mesh.positionKeys[key][special.vertex[k]];
                    ok = ok && isFinite(p);
                    box.extend(p);
                }
            if (!ok) {
                ++skippedCount_;
                continue;
            }
            addSpecial(special, padded(box, 0.0f));
        }
    }
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        const Sphere& sphere = scene.spheres[s];
        if (!sphere.motion.moves()) continue;
        SceneGeometry child;
        child.spheres.push_back(sphere);
        child.spheres[0].motion.keys.clear();
        addInstance(std::move(child), sphere.motion, sphereGeomId_, uint32_t(s));
    }
    curves_ = scene.curves;
    for (size_t c = 0; c < curves_.size(); ++c) {
        const Curves& curves = curves_[c];
        for (size_t j = 0; j < curves.segmentCount(); ++j) {
            const Vec3f* p = curves.controlPoints(j);
            const float* r = curves.controlRadii(j);
            bool ok = true;
            float radius = 0.0f, polygon = 0.0f;
            for (int k = 0; k < 4; ++k) {
                ok = ok && isFinite(p[k]) && std::isfinite(r[k]);
                radius = std::max(radius, r[k]);
                if (k > 0) polygon += length(p[k] - p[k - 1]);
            }
            if (!ok || !(radius > 0.0f)) {
                ++skippedCount_;
                continue;
            }
            // A long segment is boxed in pieces of up to about 8 widths (at most 8 pieces: pbrt-v4's
            // default splitdepth), each a special primitive that tests only its part of the
            // segment (CurvePiece).
            const float pieces = polygon / (16.0f * radius);
            const uint32_t level =
                pieces > 1.0f ? uint32_t(std::min(3.0f, std::ceil(std::log2(pieces)))) : 0u;
            for (uint32_t index = 0; index < (1u << level); ++index) {
                Special special{};
                special.geomId = scene.curvesGeomId(c);
                special.primId = uint32_t(j);
                special.source = uint32_t(c);
                special.vertex[0] = level;
                special.vertex[1] = index;
                special.cutOut = kNoHit;
                special.kind = SpecialKind::CurveSegment;
                addSpecial(special, curvePieceBox(p, r, level, index));
            }
        }
    }
    // Each bilinear patch is one, boxed by its corners (a bilinear patch lies in their hull).
    patches_ = scene.patches;
    for (size_t b = 0; b < patches_.size(); ++b) {
        const BilinearPatches& patches = patches_[b];
        for (size_t j = 0; j < patches.patchCount(); ++j) {
            Bounds3f box;
            bool ok = true;
            for (int k = 0; k < 4; ++k) {
                const uint32_t vertex = patches.indices[4 * j + k];
                ok = ok && vertex < patches.positions.size() && isFinite(patches.positions[vertex]);
                if (ok) box.extend(patches.positions[vertex]);
            }
            if (!ok) {
                ++skippedCount_;
                continue;
            }
            Special special{};
            special.geomId = scene.patchesGeomId(b);
            special.primId = uint32_t(j);
            special.source = uint32_t(b);
            special.cutOut = kNoHit;
            special.kind = SpecialKind::BilinearPatch;
            addSpecial(special, padded(box, 0.0f));
        }
    }
}

bool BvhAccelerator::keepsHit(const Special& special, const CutOutRay& cutOutRay, float b1, float b2) const {
    if (special.cutOut == kNoHit) return true;
    const CutOut& cutOut = cutOuts_[special.cutOut];
    const float alpha = cutOutCoverage(*cutOut.alpha, meshUvAt(cutOut.uvs, special.vertex, b1, b2));
    const uint32_t geomId =
        cutOutRay.instanceGeomId != kNoInstance ? cutOutRay.instanceGeomId : special.geomId;
    return keepsCutOutHit(alpha, cutOutRay.rayHash, geomId, special.primId);
}

template <bool AnyHit>
bool BvhAccelerator::intersectSpecial(const Ray& ray, const WatertightRay& triangleRay,
                                      const CutOutRay& cutOutRay, const Primitive& primitive, float tFar,
                                      float& t, float& b1, float& b2, Hit& instanceHit) const {
    if (!std::isfinite(ray.time)) return false;
    const Special& special = specials_[primitive.globalIndex - specialBase_];
    if (special.kind == SpecialKind::CurveSegment) {
        CurveHit curveHit;
        if (!intersectCurveSegment(curves_[special.source], special.primId, ray.origin, ray.direction,
                                   ray.tnear, tFar, curveHit))
            return false;
        t = curveHit.t;
        b1 = curveHit.u;
        b2 = curveHit.v;
        return true;
    }
    if (special.kind == SpecialKind::BilinearPatch) {
        const std::array<Vec3f, 4> corners = patches_[special.source].cornerPositions(special.primId);
        BilinearPatchHit patchHit;
        if (!intersectBilinearPatch(corners.data(), ray.origin, ray.direction, ray.tnear, tFar, patchHit))
            return false;
        t = patchHit.t;
        b1 = patchHit.u;
        b2 = patchHit.v;
        return true;
    }
    if (special.kind != SpecialKind::Instance) {
        TriangleHit th;
        if (special.kind == SpecialKind::StillTriangle) {
            if (!intersectTriangleWatertight(triangleRay, primitive.data, ray.tnear, tFar, th)) return false;
        } else {
            // The vertices at ray.time, exactly as geometry/surface_interaction.h computes them.
            const auto& keys = deformingMeshes_[special.source];
            const Vec3f p0 = interpolateKeys(keys, special.vertex[0], ray.time),
                        p1 = interpolateKeys(keys, special.vertex[1], ray.time),
                        p2 = interpolateKeys(keys, special.vertex[2], ray.time);
            const float vertices[9] = {p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z};
            if (!intersectTriangleWatertight(triangleRay, vertices, ray.tnear, tFar, th)) return false;
        }
        if (!keepsHit(special, cutOutRay, th.b1, th.b2)) return false;
        t = th.t;
        b1 = th.b1;
        b2 = th.b2;
        return true;
    }
    const Instance& instance = instances_[special.source];
    if (instance.motion.moves())
        return intersectInstance<AnyHit>(special, instance.motion.at(ray.time), ray, cutOutRay, tFar, t, b1,
                                         b2, instanceHit);
    return intersectInstance<AnyHit>(special, instance.placement, ray, cutOutRay, tFar, t, b1, b2,
                                     instanceHit);
}

template <bool AnyHit>
bool BvhAccelerator::intersectInstance(const Special& special, const Transform& toWorld, const Ray& ray,
                                       const CutOutRay& cutOutRay, float tFar, float& t, float& b1, float& b2,
                                       Hit& instanceHit) const {
    const Instance& instance = instances_[special.source];
    // The same transform the shading code places the hit with, and the same object-space ray that
    // hits are recomputed with (geometry/surface_interaction.h); the direction is not normalized,
    // so t is the same in both spaces.
    const Transform toObject = toWorld.inverse();
    Ray objectRay = ray;
    objectRay.origin = toObject.applyPoint(ray.origin);
    objectRay.direction = toObject.applyVector(ray.direction);
    objectRay.tfar = tFar;
    // The child's cut-outs decide with the world ray's hash and this instance's geomId.
    const CutOutRay childCutOutRay{cutOutRay.rayHash, special.geomId};
    if constexpr (AnyHit) {
        return instance.child->traverse<true>(objectRay, nullptr, childCutOutRay);
    } else {
        Hit h;
        if (!instance.child->traverse<false>(objectRay, &h, childCutOutRay)) return false;
        t = h.t;
        b1 = h.u;
        b2 = h.v;
        instanceHit = h;
        instanceHit.geometricNormal = toWorld.applyNormal(h.geometricNormal);
        instanceHit.geomId = special.geomId;
        if (special.primId != kNoHit) instanceHit.primId = special.primId;
        return true;
    }
}

BvhAccelerator::Stats BvhAccelerator::stats() const {
    Stats s;
    s.nodeCount = nodes_.size();
    s.leafCount = leafCount_;
    s.primitiveCount = primitiveCount_;
    s.skippedCount = skippedCount_;
    s.maxDepth = maxDepth_;
    s.sahCost = sahCost_;
    s.memoryBytes = nodes_.capacity() * sizeof(Bvh4Node) + blocks_.capacity() * sizeof(PrimitiveBlock) +
                    meshFirstTriangle_.capacity() * sizeof(uint32_t) + specials_.capacity() * sizeof(Special);
    for (const auto& keys : deformingMeshes_)
        for (const auto& key : keys) s.memoryBytes += key.capacity() * sizeof(Vec3f);
    for (const CutOut& cutOut : cutOuts_)
        s.memoryBytes += sizeof(CutOut) + cutOut.uvs.capacity() * sizeof(Vec2f);
    // Each tree once, however many instances share it.
    s.memoryBytes += instances_.capacity() * sizeof(Instance);
    for (const auto& child : children_) {
        const Stats c = child->stats();
        s.memoryBytes += c.memoryBytes;
        s.primitiveCount += c.primitiveCount;
    }
    return s;
}

// Asks for what child i of `node` leads to (its node, two cache lines, or its first block)
// as soon as the ray is known to enter it: incoherent rays wait on memory more than they compute,
// and these loads then overlap with each other and with the work on nearer children.
void BvhAccelerator::prefetchChild(const Bvh4Node& node, int i) const {
    if (node.isLeaf(i)) {
        // A block spans three cache lines, and the test reads its last one first.
        const char* p = reinterpret_cast<const char*>(&blocks_[node.child[i]]);
        __builtin_prefetch(p);
        __builtin_prefetch(p + 64);
        __builtin_prefetch(p + sizeof(PrimitiveBlock) - 1);
    } else {
        const char* p = reinterpret_cast<const char*>(&nodes_[node.child[i]]);
        __builtin_prefetch(p);
        __builtin_prefetch(p + 64);
    }
}

namespace {

// A child still to visit, with the distance where the ray enters its box.
struct PendingChild {
    uint32_t child;  // as Bvh4Node::child
    uint32_t count;  // as Bvh4Node::count: 0 for an interior node
    float tEntry;
};

inline void orderFarToNear(PendingChild& a, PendingChild& b) {
    if (a.tEntry < b.tEntry) std::swap(a, b);
}

// Sorts 2 to 4 pending children by entry distance, the nearest last (on top of the stack), with
// sorting networks (Knuth, TAOCP vol. 3, section 5.3.4). Equal distances keep their slot order.
inline void sortFarToNear(PendingChild* c, int n) {
    if (n == 2) {
        orderFarToNear(c[0], c[1]);
    } else if (n == 3) {
        orderFarToNear(c[0], c[1]);
        orderFarToNear(c[1], c[2]);
        orderFarToNear(c[0], c[1]);
    } else {
        orderFarToNear(c[0], c[1]);
        orderFarToNear(c[2], c[3]);
        orderFarToNear(c[0], c[2]);
        orderFarToNear(c[1], c[3]);
        orderFarToNear(c[1], c[2]);
    }
}

}  // namespace

namespace {

// Bit l set when lane l of the block holds a triangle (a global index below triangleCount, compared
// unsigned: SSE2 compares signed, so both sides have their sign bits flipped).
inline int triangleLanes(const uint32_t* globalIndex, uint32_t triangleCount) {
    const __m128i flip = _mm_set1_epi32(int32_t(0x80000000u));
    const __m128i index = _mm_xor_si128(_mm_load_si128(reinterpret_cast<const __m128i*>(globalIndex)), flip);
    const __m128i bound = _mm_xor_si128(_mm_set1_epi32(int32_t(triangleCount)), flip);
    return _mm_movemask_ps(_mm_castsi128_ps(_mm_cmplt_epi32(index, bound)));
}

}  // namespace

// A block of triangles only (nearly every block) is tested four at a time. The result is the one
// primitive-by-primitive testing in leaf order gives (each test accepting t <= the closest t so
// far): the smallest t, and of equal ones the last in leaf order. Other blocks go one by one.
template <bool AnyHit>
bool BvhAccelerator::intersectLeaf(const Ray& ray, const WatertightRay& triangleRay,
                                   const WatertightRay4& triangleRay4, const CutOutRay& cutOutRay,
                                   uint32_t firstBlock, uint32_t count, float& tClosest, uint32_t& closest,
                                   float& closestB1, float& closestB2, Hit& instanceHit) const {
    bool found = false;
    for (uint32_t b = firstBlock; count > 0; ++b) {
        const int lanes = count < 4 ? int(count) : 4;
        count -= uint32_t(lanes);
        const PrimitiveBlock& block = blocks_[b];
        const int used = (1 << lanes) - 1;
        if ((triangleLanes(block.globalIndex, triangleCount_) & used) == used) {
            TriangleHits4 h;
            intersectTrianglesWatertight4(triangleRay4, block.data, ray.tnear, tClosest, h);
            int hit = h.hit & used;
            for (int rest = h.fallback & used; rest != 0; rest &= rest - 1) {
                const int lane = __builtin_ctz(unsigned(rest));
                const Primitive p = primitiveAt(block, lane);
                TriangleHit th;
                if (!intersectTriangleWatertight(triangleRay, p.data, ray.tnear, tClosest, th)) continue;
                h.t[lane] = th.t;
                h.b1[lane] = th.b1;
                h.b2[lane] = th.b2;
                hit |= 1 << lane;
            }
            if (hit == 0) continue;
            if constexpr (AnyHit) return true;
            int best = __builtin_ctz(unsigned(hit));
            for (int rest = hit & (hit - 1); rest != 0; rest &= rest - 1) {
                const int lane = __builtin_ctz(unsigned(rest));
                if (h.t[lane] <= h.t[best]) best = lane;
            }
            tClosest = h.t[best];
            closestB1 = h.b1[best];
            closestB2 = h.b2[best];
            closest = 4 * b + uint32_t(best);
            found = true;
            continue;
        }
        for (int lane = 0; lane < lanes; ++lane) {
            const Primitive p = primitiveAt(block, lane);
            float t, b1 = 0.0f, b2 = 0.0f;
            if (p.globalIndex < triangleCount_) {
                TriangleHit th;
                if (!intersectTriangleWatertight(triangleRay, p.data, ray.tnear, tClosest, th)) continue;
                t = th.t;
                b1 = th.b1;
                b2 = th.b2;
            } else if (p.globalIndex < specialBase_) {
                if (!intersectSphere(ray.origin, ray.direction, {p.data[0], p.data[1], p.data[2]}, p.data[3],
                                     ray.tnear, tClosest, t))
                    continue;
            } else {
                if (!intersectSpecial<AnyHit>(ray, triangleRay, cutOutRay, p, tClosest, t, b1, b2,
                                              instanceHit))
                    continue;
            }
            if constexpr (AnyHit) return true;
            tClosest = t;
            closestB1 = b1;
            closestB2 = b2;
            closest = 4 * b + uint32_t(lane);
            found = true;
        }
    }
    return found;
}

template <bool AnyHit>
bool BvhAccelerator::traverse(const Ray& ray, Hit* hit, const CutOutRay& cutOutRay) const {
    if (nodes_.empty() || !isTraceable(ray)) return false;
    const BoxRay4 boxRay(ray.origin, ray.direction, ray.tnear);
    const WatertightRay triangleRay(ray.origin, ray.direction);
    const WatertightRay4 triangleRay4(triangleRay);

    float tClosest = ray.tfar;
    uint32_t closest = kNoHit;
    float closestB1 = 0.0f, closestB2 = 0.0f;
    Hit instanceHit;  // the closest hit's, when it is a moving instance

    // Children still to visit: one deferred child entered beyond the closest hit found since is
    // skipped. Each level of the tree (at most kBvhMaxDepth) leaves at most kBvhWidth - 1 waiting.
    PendingChild stack[(kBvhWidth - 1) * kBvhMaxDepth];
    int top = 0;
    PendingChild current{0, 0, ray.tnear};  // the root
    for (;;) {
        if (current.count == 0) {
            const Bvh4Node& node = nodes_[current.child];
            __m128 tEntry4;
            int mask = intersectBoxes4(node, boxRay, tClosest, tEntry4);
            if (mask != 0) {
                alignas(16) float tEntry[kBvhWidth];
                _mm_store_ps(tEntry, tEntry4);
                if ((mask & (mask - 1)) == 0) {  // one child: straight there
                    const int i = __builtin_ctz(unsigned(mask));
                    current = {node.child[i], node.count[i], tEntry[i]};
                    continue;
                }
                // Several: all pushed, sorted so the nearest is on top, and that one taken now.
                // occluded() takes them as they come: any hit ends it, and sorting cost more than
                // finding a blocker sooner saved (bench/README.md, "Speed tricks").
                const int first = top;
                do {
                    const int i = __builtin_ctz(unsigned(mask));
                    mask &= mask - 1;
                    prefetchChild(node, i);
                    assert(top < int(std::size(stack)));
                    stack[top++] = {node.child[i], node.count[i], tEntry[i]};
                } while (mask != 0);
                if constexpr (!AnyHit) sortFarToNear(stack + first, top - first);
                current = stack[--top];
                continue;
            }
        } else {
            if (intersectLeaf<AnyHit>(ray, triangleRay, triangleRay4, cutOutRay, current.child, current.count,
                                      tClosest, closest, closestB1, closestB2, instanceHit)) {
                if constexpr (AnyHit) return true;
            }
        }
        // Next: the most recently deferred child that may still hold something nearer.
        for (;;) {
            if (top == 0) {
                if (closest == kNoHit) return false;
                PENUMBRA_CHECK(tClosest >= ray.tnear && tClosest <= ray.tfar,
                               "a hit lies within [tnear, tfar]");
                if constexpr (!AnyHit)
                    fillHit(ray, closest, tClosest, closestB1, closestB2, instanceHit, *hit);
                return true;
            }
            const PendingChild& pending = stack[--top];
            if (pending.tEntry <= tClosest) {
                current = pending;
                break;
            }
        }
    }
}

void BvhAccelerator::fillHit(const Ray& ray, uint32_t primitive, float t, float b1, float b2,
                             const Hit& specialHit, Hit& hit) const {
    const Primitive p = primitiveAt(blocks_[primitive / 4], int(primitive % 4));
    hit.t = t;
    hit.u = b1;
    hit.v = b2;
    if (p.globalIndex < triangleCount_) {
        // The watertight test's barycentrics: e1 / det and e2 / det with e0, e1, e2 of det's sign, so
        // in [0, 1] and summing to at most 1, up to the roundings of det and of the two quotients.
        PENUMBRA_CHECK(b1 >= 0.0f && b2 >= 0.0f && b1 + b2 <= 1.0f + 1e-6f,
                       "a triangle hit's barycentrics lie in it");
        const Vec3f p0(p.data[0], p.data[1], p.data[2]), p1(p.data[3], p.data[4], p.data[5]),
            p2(p.data[6], p.data[7], p.data[8]);
        hit.geometricNormal = cross(p1 - p0, p2 - p0);
        // The mesh whose range holds the index: the last one starting at or before it.
        const auto next =
            std::upper_bound(meshFirstTriangle_.begin(), meshFirstTriangle_.end(), p.globalIndex);
        const size_t mesh = size_t(next - meshFirstTriangle_.begin()) - 1;
        hit.geomId = uint32_t(mesh);
        hit.primId = p.globalIndex - meshFirstTriangle_[mesh];
    } else if (p.globalIndex >= specialBase_) {
        const Special& special = specials_[p.globalIndex - specialBase_];
        if (special.kind == SpecialKind::Instance) {
            hit = specialHit;
            hit.t = t;
            return;
        }
        if (special.kind == SpecialKind::CurveSegment) {
            // As Embree reports flat curves' hits: the curve's tangent.
            hit.geometricNormal =
                curve::bezierDerivative(curves_[special.source].controlPoints(special.primId), b1);
        } else if (special.kind == SpecialKind::BilinearPatch) {
            // As our Embree user geometry reports it: cross(dp/du, dp/dv).
            const std::array<Vec3f, 4> p = patches_[special.source].cornerPositions(special.primId);
            hit.geometricNormal = cross(bilinear::dpdu(p.data(), b2), bilinear::dpdv(p.data(), b1));
        } else if (special.kind == SpecialKind::StillTriangle) {
            const Vec3f p0(p.data[0], p.data[1], p.data[2]), p1(p.data[3], p.data[4], p.data[5]),
                p2(p.data[6], p.data[7], p.data[8]);
            hit.geometricNormal = cross(p1 - p0, p2 - p0);
        } else {
            const auto& keys = deformingMeshes_[special.source];
            const Vec3f p0 = interpolateKeys(keys, special.vertex[0], ray.time),
                        p1 = interpolateKeys(keys, special.vertex[1], ray.time),
                        p2 = interpolateKeys(keys, special.vertex[2], ray.time);
            hit.geometricNormal = cross(p1 - p0, p2 - p0);
        }
        hit.geomId = special.geomId;
        hit.primId = special.primId;
    } else {
        // As Embree reports sphere hits: the unnormalized normal is the hit point minus the centre.
        hit.geometricNormal = ray.at(t) - Vec3f(p.data[0], p.data[1], p.data[2]);
        hit.geomId = sphereGeomId_;
        hit.primId = p.globalIndex - triangleCount_;
    }
}

bool BvhAccelerator::intersect(const Ray& ray, Hit& hit) const {
    return traverse<false>(ray, &hit, CutOutRay{hasCutOuts_ ? cutOutRayHash(ray) : 0});
}

bool BvhAccelerator::occluded(const Ray& ray) const {
    return traverse<true>(ray, nullptr, CutOutRay{hasCutOuts_ ? cutOutRayHash(ray) : 0});
}

}  // namespace penumbra
