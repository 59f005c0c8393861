#include "tools/crosscheck.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "cameras/camera.h"
#include "core/frame.h"
#include "core/hash.h"
#include "core/ray_offset.h"
#include "core/sampling.h"
#include "formats/scene_file.h"
#include "geometry/cut_out.h"
#include "geometry/surface_interaction.h"
#include "geometry/triangle.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kMaxBounces = 4;
// Shadow segments stop this short of their (offset) target, as the integrator's do.
constexpr float kShadowRayEnd = 1.0f - 0x1p-20f;

// Uniform numbers for one ray: a hash of (seed, kind, index, dimension).
class RayRandom {
public:
    RayRandom(uint64_t seed, CrosscheckRayKind kind, uint64_t index)
        : seed_(seed), kind_(uint64_t(kind)), index_(index) {}
    float next() { return bitsToUnitFloat(uint32_t(hashWords(seed_, kind_, index_, dimension_++) >> 32)); }
    Vec2f next2() {
        const float a = next();
        return {a, next()};
    }

private:
    uint64_t seed_, kind_, index_;
    uint64_t dimension_ = 0;
};

struct SceneExtent {
    Vec3f lower{-1.0f, -1.0f, -1.0f}, upper{1.0f, 1.0f, 1.0f};
};

SceneExtent measureScene(const Scene& scene) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    Vec3f lower{inf, inf, inf}, upper{-inf, -inf, -inf};
    for (const TriangleMesh& mesh : scene.meshes)
        for (const Vec3f& p : mesh.positions)
            if (isFinite(p)) {
                lower = min(lower, p);
                upper = max(upper, p);
            }
    for (const Sphere& s : scene.spheres) {
        const Vec3f r(s.radius, s.radius, s.radius);
        lower = min(lower, s.center - r);
        upper = max(upper, s.center + r);
    }
    for (const Curves& curves : scene.curves)
        for (const Vec3f& p : curves.points)
            if (isFinite(p)) lower = min(lower, p), upper = max(upper, p);
    for (const BilinearPatches& patches : scene.patches)
        for (const Vec3f& p : patches.positions)
            if (isFinite(p)) lower = min(lower, p), upper = max(upper, p);
    // Instances: the corners of their prototype's box, placed at the shutter's opening and closing.
    std::vector<std::pair<Vec3f, Vec3f>> prototypeBoxes;
    for (const TriangleMesh& prototype : scene.prototypes) {
        Vec3f a{inf, inf, inf}, b{-inf, -inf, -inf};
        for (const Vec3f& p : prototype.positions) a = min(a, p), b = max(b, p);
        prototypeBoxes.emplace_back(a, b);
    }
    for (const MeshInstance& instance : scene.instances) {
        const auto [a, b] = prototypeBoxes[instance.prototype];
        if (!(a.x <= b.x)) continue;
        for (const float time : {0.0f, 1.0f})
            for (int c = 0; c < 8; ++c) {
                const Vec3f p = instance.toWorld(time).applyPoint(
                    {(c & 1) ? b.x : a.x, (c & 2) ? b.y : a.y, (c & 4) ? b.z : a.z});
                if (isFinite(p)) lower = min(lower, p), upper = max(upper, p);
            }
    }
    if (!(lower.x <= upper.x && lower.y <= upper.y && lower.z <= upper.z)) return {};
    return {lower, upper};
}

// Every primitive of the scene by one global index: triangles of all meshes in order, then spheres,
// then the triangles of all instances in order, the segments of all curve sets, and the patches of
// all bilinear patch sets.
class PrimitiveIndex {
public:
    explicit PrimitiveIndex(const Scene& scene) : scene_(scene) {
        uint64_t total = 0;
        for (const TriangleMesh& mesh : scene.meshes) {
            first_.push_back(total);
            total += mesh.triangleCount();
        }
        first_.push_back(total);
        triangles_ = total;
        total = 0;
        for (const MeshInstance& instance : scene.instances) {
            instanceFirst_.push_back(total);
            total += scene.prototypes[instance.prototype].triangleCount();
        }
        instanceFirst_.push_back(total);
        total = 0;
        for (const Curves& curves : scene.curves) {
            curvesFirst_.push_back(total);
            total += curves.segmentCount();
        }
        curvesFirst_.push_back(total);
        total = 0;
        for (const BilinearPatches& patches : scene.patches) {
            patchesFirst_.push_back(total);
            total += patches.patchCount();
        }
        patchesFirst_.push_back(total);
    }
    uint64_t count() const {
        return triangles_ + scene_.spheres.size() + instanceFirst_.back() + curvesFirst_.back() +
               patchesFirst_.back();
    }

    struct Point {
        Vec3f position, positionError, normal;
        uint32_t geomId = 0, primId = 0;
    };
    // A uniformly chosen point on primitive `g`.
    Point sample(uint64_t g, Vec2f u) const {
        Point point;
        if (g >= triangles_ + scene_.spheres.size() + instanceFirst_.back() + curvesFirst_.back())
            return samplePatch(
                g - triangles_ - scene_.spheres.size() - instanceFirst_.back() - curvesFirst_.back(), u);
        if (g >= triangles_ + scene_.spheres.size() + instanceFirst_.back())
            return sampleCurve(g - triangles_ - scene_.spheres.size() - instanceFirst_.back(), u);
        if (g >= triangles_ + scene_.spheres.size())
            return sampleInstance(g - triangles_ - scene_.spheres.size(), u);
        if (g >= triangles_) {
            const Sphere& s = scene_.spheres[g - triangles_];
            point.normal = sampleUniformSphere(u);
            point.position = s.center + point.normal * s.radius;
            point.positionError = (abs(s.center) + abs(point.normal * s.radius)) * gamma(8);
            const Hit ids = scene_.idsOf({ShapeKind::Sphere, uint32_t(g - triangles_), 0});
            point.geomId = ids.geomId;
            point.primId = ids.primId;
            return point;
        }
        const size_t m = size_t(std::upper_bound(first_.begin(), first_.end(), g) - first_.begin()) - 1;
        const TriangleMesh& mesh = scene_.meshes[m];
        const size_t j = size_t(g - first_[m]);
        const Vec3f p0 = mesh.positions[mesh.indices[3 * j]], p1 = mesh.positions[mesh.indices[3 * j + 1]],
                    p2 = mesh.positions[mesh.indices[3 * j + 2]];
        const Vec2f b = sampleUniformTriangle(u);
        point.position = p0 * (1.0f - b.x - b.y) + p1 * b.x + p2 * b.y;
        point.positionError = (abs(p0 * (1.0f - b.x - b.y)) + abs(p1 * b.x) + abs(p2 * b.y)) * gamma(7);
        const Vec3f n = cross(p1 - p0, p2 - p0);
        const float nLength = length(n);
        point.normal = nLength > 0.0f ? n / nLength : Vec3f{0.0f, 0.0f, 1.0f};
        const Hit ids = scene_.idsOf({ShapeKind::Mesh, uint32_t(m), uint32_t(j)});
        point.geomId = ids.geomId;
        point.primId = ids.primId;
        return point;
    }

private:
    // A point on instance triangle `g` (counted over all instances), placed where the instance is
    // at the shutter's opening.
    Point sampleInstance(uint64_t g, Vec2f u) const {
        const size_t k = size_t(std::upper_bound(instanceFirst_.begin(), instanceFirst_.end(), g) -
                                instanceFirst_.begin()) -
                         1;
        const TriangleMesh& mesh = scene_.prototypes[scene_.instances[k].prototype];
        const size_t j = size_t(g - instanceFirst_[k]);
        const Vec3f p0 = mesh.positions[mesh.indices[3 * j]], p1 = mesh.positions[mesh.indices[3 * j + 1]],
                    p2 = mesh.positions[mesh.indices[3 * j + 2]];
        const Vec2f b = sampleUniformTriangle(u);
        SurfaceInteraction si;
        si.position = p0 * (1.0f - b.x - b.y) + p1 * b.x + p2 * b.y;
        si.positionError = (abs(p0 * (1.0f - b.x - b.y)) + abs(p1 * b.x) + abs(p2 * b.y)) * gamma(7);
        const Vec3f n = triangleNormal(p0, p1, p2);
        si.geometricNormal = si.shadingNormal = n != Vec3f{0.0f, 0.0f, 0.0f} ? n : Vec3f{0.0f, 0.0f, 1.0f};
        const Transform toWorld = scene_.instances[k].toWorld(0.0f);
        detail::placeInWorld(toWorld, si);
        Point point;
        point.position = si.position;
        point.positionError = si.positionError;
        point.normal = si.geometricNormal;
        const Hit ids = scene_.idsOf({ShapeKind::Instance, uint32_t(k), uint32_t(j)});
        point.geomId = ids.geomId;
        point.primId = ids.primId;
        return point;
    }

    // A point on the centre line of curve segment `g` (counted over all curve sets), its error
    // bound and normal as a hit's there (geometry/surface_interaction.h): a shadow ray towards it
    // ends off the curve, as one towards a surface point does.
    Point sampleCurve(uint64_t g, Vec2f u) const {
        const size_t c =
            size_t(std::upper_bound(curvesFirst_.begin(), curvesFirst_.end(), g) - curvesFirst_.begin()) - 1;
        const Curves& curves = scene_.curves[c];
        const size_t j = size_t(g - curvesFirst_[c]);
        Point point;
        point.position = curve::bezier(curves.controlPoints(j), u.x);
        const float width = 2.0f * std::abs(curve::bezier(curves.controlRadii(j), u.x));
        point.positionError = Vec3f{1.0f, 1.0f, 1.0f} * (2.0f * width) + abs(point.position) * gamma(4);
        const Vec3f tangent = curve::bezierDerivative(curves.controlPoints(j), u.x);
        point.normal =
            length(tangent) > 0.0f ? Frame::fromNormal(normalize(tangent)).s : Vec3f{0.0f, 0.0f, 1.0f};
        const Hit ids = scene_.idsOf({ShapeKind::Curves, uint32_t(c), uint32_t(j)});
        point.geomId = ids.geomId;
        point.primId = ids.primId;
        return point;
    }

    // A point of bilinear patch `g` (counted over all patch sets) at (u, v) = `u`, with its error
    // bound and normal as a hit's there (geometry/surface_interaction.h).
    Point samplePatch(uint64_t g, Vec2f u) const {
        const size_t b =
            size_t(std::upper_bound(patchesFirst_.begin(), patchesFirst_.end(), g) - patchesFirst_.begin()) -
            1;
        const BilinearPatches& patches = scene_.patches[b];
        const size_t j = size_t(g - patchesFirst_[b]);
        const std::array<Vec3f, 4> p = patches.cornerPositions(j);
        Point point;
        point.position = bilinear::point(p.data(), u.x, u.y);
        point.positionError = bilinear::pointError(p.data());
        const Vec3f n = cross(bilinear::dpdu(p.data(), u.y), bilinear::dpdv(p.data(), u.x));
        point.normal = length(n) > 0.0f ? normalize(n) : Vec3f{0.0f, 0.0f, 1.0f};
        const Hit ids = scene_.idsOf({ShapeKind::BilinearPatches, uint32_t(b), uint32_t(j)});
        point.geomId = ids.geomId;
        point.primId = ids.primId;
        return point;
    }

    const Scene& scene_;
    std::vector<uint64_t> first_;
    uint64_t triangles_ = 0;
    std::vector<uint64_t> instanceFirst_;  // each instance's first triangle, then the total
    std::vector<uint64_t> curvesFirst_;    // each curve set's first segment, then the total
    std::vector<uint64_t> patchesFirst_;   // each bilinear patch set's first patch, then the total
};

Ray makeRandomRay(const SceneExtent& extent, RayRandom& random) {
    Ray ray;
    const Vec3f d = extent.upper - extent.lower;
    const float ux = random.next(), uy = random.next(), uz = random.next();
    ray.origin = {extent.lower.x + ux * d.x, extent.lower.y + uy * d.y, extent.lower.z + uz * d.z};
    ray.direction = sampleUniformSphere(random.next2());
    return ray;
}

Ray makeCameraRay(const Scene& scene, const Camera& camera, RayRandom& random) {
    const Vec2f film = random.next2();
    const Vec2f lens = random.next2();
    return camera
        .generateRay({film.x * float(scene.film.width), film.y * float(scene.film.height)}, lens,
                     random.next())
        .ray;
}

// A segment from a surface point to a point on another surface, both ends moved off their
// surfaces, as the integrator's shadow rays are (renderer/path_integrator.h).
Ray makeShadowRay(Vec3f from, Vec3f fromError, Vec3f fromNormal, const PrimitiveIndex::Point& to,
                  float time) {
    const Vec3f toTarget = to.position - from;
    const Vec3f side = dot(toTarget, fromNormal) >= 0.0f ? fromNormal : -fromNormal;
    Ray ray;
    ray.origin = offsetRayOrigin(from, fromError, side);
    const Vec3f target =
        offsetRayOrigin(to.position, to.positionError, faceForward(to.normal, ray.origin - to.position));
    ray.direction = target - ray.origin;
    ray.tfar = kShadowRayEnd;
    ray.time = time;
    return ray;
}

// `ray` marked as leaving the surface of `hit` at `si`.
CrosscheckRay leaving(const Hit& hit, const SurfaceInteraction& si, CrosscheckRay ray) {
    ray.leavesSurface = true;
    ray.sourceGeomId = hit.geomId;
    ray.sourcePrimId = hit.primId;
    ray.sourceDistance = length(ray.ray.origin - si.position) + length(si.positionError);
    return ray;
}

// |a - b| relative to the larger magnitude.
double relativeDifference(double a, double b) {
    const double scale = std::max(std::abs(a), std::abs(b));
    return scale > 0.0 ? std::abs(a - b) / scale : 0.0;
}

bool isTriangleHit(const Scene& scene, const Hit& hit) { return scene.shapeOf(hit).isTriangle(); }

// The triangle `ray` leaves, if it leaves one.
TriangleLeft triangleLeft(const Scene& scene, const CrosscheckRay& ray) {
    if (!ray.leavesSurface) return {};
    Hit source;
    source.geomId = ray.sourceGeomId;
    source.primId = ray.sourcePrimId;
    return isTriangleHit(scene, source) ? TriangleLeft{source.geomId, source.primId} : TriangleLeft{};
}

bool isNearEdge(const Scene& scene, const Hit& hit) {
    if (scene.shapeOf(hit).kind == ShapeKind::BilinearPatches)
        return std::min(std::min(hit.u, 1.0f - hit.u), std::min(hit.v, 1.0f - hit.v)) < kEdgeTolerance;
    if (!isTriangleHit(scene, hit)) return false;
    const float b0 = 1.0f - hit.u - hit.v;
    return std::min(b0, std::min(hit.u, hit.v)) < kEdgeTolerance;
}

float incidenceCosine(const Scene& scene, const Ray& ray, const Hit& hit) {
    Vec3f normal;
    const ShapeRef shape = scene.shapeOf(hit);
    if (shape.kind == ShapeKind::Curves) {
        // A flat curve faces the ray: it is grazed only by a ray along its tangent.
        const Vec3f tangent = curve::bezierDerivative(
            scene.curves[shape.index].controlPoints(shape.primitive), std::clamp(hit.u, 0.0f, 1.0f));
        const float denominator = length(tangent) * length(ray.direction);
        if (!(denominator > 0.0f)) return 0.0f;
        const float cosine = std::min(1.0f, std::abs(dot(tangent, ray.direction)) / denominator);
        return std::sqrt(1.0f - cosine * cosine);
    }
    if (shape.kind == ShapeKind::BilinearPatches) {
        const std::array<Vec3f, 4> p = scene.patches[shape.index].cornerPositions(shape.primitive);
        normal = cross(bilinear::dpdu(p.data(), hit.v), bilinear::dpdv(p.data(), hit.u));
    } else if (shape.kind != ShapeKind::Sphere) {
        const TriangleMesh& mesh = scene.triangleMeshOf(shape);
        const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
        const Vec3f p0 = mesh.positions[index[0]], p1 = mesh.positions[index[1]],
                    p2 = mesh.positions[index[2]];
        normal = cross(p1 - p0, p2 - p0);
        if (shape.kind == ShapeKind::Instance) normal = scene.toWorldOf(shape, ray.time).applyNormal(normal);
    } else {
        normal = ray.at(hit.t) - scene.spheres[shape.index].center;
    }
    const float denominator = length(normal) * length(ray.direction);
    return denominator > 0.0f ? std::abs(dot(normal, ray.direction)) / denominator : 0.0f;
}

bool samePrimitive(const Hit& a, const Hit& b) { return a.geomId == b.geomId && a.primId == b.primId; }

std::string hexFloat(float value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%a", double(value));
    return buffer;
}

std::string describeAnswer(const CrosscheckRay& ray, const BackendAnswer& answer) {
    if (!answer.hitSomething) return ray.isSegment() ? "not blocked" : "miss";
    std::string text = ray.isSegment() ? "blocked" : "hit";
    if (answer.hasHit) {
        const Hit& h = answer.hit;
        text += fmt::format(" geom {} prim {} at t {} ({:.9g}), u {:.9g}, v {:.9g}", h.geomId, h.primId,
                            hexFloat(h.t), h.t, h.u, h.v);
    }
    return text;
}

template <typename Accel>
double measureRaysPerSecond(const Accel& accel, const std::vector<CrosscheckRay>& rays) {
    if (rays.empty()) return 0.0;
    // The backends live in other translation units, so these calls cannot be optimized away.
    const auto start = Clock::now();
    for (const CrosscheckRay& r : rays) {
        if (r.isSegment()) {
            (void)accel.occluded(r.ray);
        } else {
            Hit hit;
            (void)accel.intersect(r.ray, hit);
        }
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return seconds > 0.0 ? double(rays.size()) / seconds : 0.0;
}

}  // namespace

const char* crosscheckRayKindName(CrosscheckRayKind kind) {
    switch (kind) {
        case CrosscheckRayKind::Camera:
            return "camera";
        case CrosscheckRayKind::Bounce:
            return "bounce";
        case CrosscheckRayKind::Shadow:
            return "shadow";
        case CrosscheckRayKind::Random:
            return "random";
    }
    return "?";
}

const char* mismatchKindName(MismatchKind kind) {
    switch (kind) {
        case MismatchKind::EdgeOrVertex:
            return "edge or vertex";
        case MismatchKind::Tie:
            return "tie";
        case MismatchKind::Grazing:
            return "grazing";
        case MismatchKind::RangeBoundary:
            return "range boundary";
        case MismatchKind::CutOutEdge:
            return "cut-out edge";
        case MismatchKind::CurveApproximation:
            return "curve approximation";
        case MismatchKind::SelfIntersection:
            return "self-intersection";
        case MismatchKind::Unexplained:
            return "unexplained";
    }
    return "?";
}

std::vector<CrosscheckRay> generateCrosscheckRays(const Scene& scene, const EmbreeAccelerator& reference,
                                                  const CrosscheckOptions& options) {
    const uint64_t perKind = options.rays / kCrosscheckRayKindCount;
    const uint64_t randomCount = options.rays - 3 * perKind;
    const Camera camera(scene.camera, scene.film.width, scene.film.height);
    const SceneExtent extent = measureScene(scene);
    const PrimitiveIndex primitives(scene);

    std::vector<CrosscheckRay> rays;
    rays.reserve(options.rays);
    for (uint64_t i = 0; i < perKind; ++i) {
        RayRandom random(options.seed, CrosscheckRayKind::Camera, i);
        rays.push_back({makeCameraRay(scene, camera, random), CrosscheckRayKind::Camera, i});
    }

    // Paths: a camera ray (or, when it escapes, a random ray) and up to kMaxBounces cosine-weighted
    // bounces, straight on through medium boundaries (interface materials) as the volumetric
    // integrator goes; every path vertex gives a bounce ray and a shadow ray to a random point
    // elsewhere.
    std::vector<CrosscheckRay> bounces, shadows;
    const uint64_t maxPaths = 16 * perKind + 1024;  // enough unless the scene is nearly invisible
    for (uint64_t path = 0; path < maxPaths && (bounces.size() < perKind || shadows.size() < perKind);
         ++path) {
        RayRandom random(options.seed, CrosscheckRayKind::Bounce, path);
        Ray ray = makeCameraRay(scene, camera, random);
        Hit hit;
        bool found = reference.intersect(ray, hit);
        if (!found) {
            ray = makeRandomRay(extent, random);
            found = reference.intersect(ray, hit);
        }
        for (int depth = 0; found && depth < kMaxBounces; ++depth) {
            const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
            const Vec3f normal = faceForward(si.geometricNormal, -ray.direction);
            if (shadows.size() < perKind && primitives.count() > 1) {
                const float pick = random.next();
                const uint64_t target =
                    std::min(uint64_t(pick * double(primitives.count())), primitives.count() - 1);
                const PrimitiveIndex::Point point = primitives.sample(target, random.next2());
                if (point.geomId != hit.geomId || point.primId != hit.primId)
                    shadows.push_back(leaving(
                        hit, si,
                        {makeShadowRay(si.position, si.positionError, si.geometricNormal, point, ray.time),
                         CrosscheckRayKind::Shadow, shadows.size()}));
            }
            Ray next;
            // (Scenes made for traversal alone may name no materials.)
            if (si.material < scene.materials.size() && scene.materials[si.material].isInterface()) {
                // A medium boundary: the volumetric integrator's ray goes straight on through it.
                next.origin = offsetRayOrigin(si.position, si.positionError, -normal);
                next.direction = ray.direction;
            } else {
                next.origin = offsetRayOrigin(si.position, si.positionError, normal);
                next.direction = Frame::fromNormal(normal).toWorld(sampleCosineHemisphere(random.next2()));
            }
            next.time = ray.time;
            if (bounces.size() < perKind)
                bounces.push_back(leaving(hit, si, {next, CrosscheckRayKind::Bounce, bounces.size()}));
            ray = next;
            found = reference.intersect(ray, hit);
        }
    }
    rays.insert(rays.end(), bounces.begin(), bounces.end());
    rays.insert(rays.end(), shadows.begin(), shadows.end());

    // Whatever the paths could not provide is made up with random rays.
    const uint64_t randomTotal = randomCount + (perKind - bounces.size()) + (perKind - shadows.size());
    for (uint64_t i = 0; i < randomTotal; ++i) {
        RayRandom random(options.seed, CrosscheckRayKind::Random, i);
        rays.push_back({makeRandomRay(extent, random), CrosscheckRayKind::Random, i});
    }
    return rays;
}

MismatchClassifier::MismatchClassifier(const Scene& scene) : scene_(scene) {
    const SceneExtent extent = measureScene(scene);
    coordinateMagnitude_ = std::max(maxComponent(abs(extent.lower)), maxComponent(abs(extent.upper)));
    if (!(coordinateMagnitude_ > 0.0f)) coordinateMagnitude_ = 1.0f;
}

double MismatchClassifier::pointDistance(const Ray& ray, float a, float b) const {
    return std::abs(double(a) - double(b)) * double(length(ray.direction)) / double(coordinateMagnitude_);
}

bool MismatchClassifier::sameDistance(const Ray& ray, float a, float b) const {
    const double travelled =
        std::max(std::abs(double(a)), std::abs(double(b))) * double(length(ray.direction));
    return std::abs(double(a) - double(b)) * double(length(ray.direction)) <=
           double(kDistanceTolerance) * (travelled + double(coordinateMagnitude_));
}

std::optional<MismatchKind> MismatchClassifier::explainHit(const Ray& ray, const Hit& hit) const {
    if (isNearEdge(scene_, hit)) return MismatchKind::EdgeOrVertex;
    if (incidenceCosine(scene_, ray, hit) < kGrazingCosine) return MismatchKind::Grazing;
    if (sameDistance(ray, hit.t, ray.tnear) || withinTriangleTestError(ray, hit) ||
        (std::isfinite(ray.tfar) && sameDistance(ray, hit.t, ray.tfar)))
        return MismatchKind::RangeBoundary;
    if (isCutOutEdge(ray, hit)) return MismatchKind::CutOutEdge;
    if (isCurveApproximation(ray, hit)) return MismatchKind::CurveApproximation;
    return std::nullopt;
}

bool MismatchClassifier::isCurveApproximation(const Ray& ray, const Hit& hit, const Hit* other) const {
    const ShapeRef shape = scene_.shapeOf(hit);
    if (shape.kind != ShapeKind::Curves) return false;
    const Curves& curves = scene_.curves[shape.index];
    const Vec3f* p = curves.controlPoints(shape.primitive);
    const float* r = curves.controlRadii(shape.primitive);
    const float u = std::clamp(hit.u, 0.0f, 1.0f);
    const float radius = curve::bezier(r, u);
    if (!(radius > 0.0f)) return true;
    // Embree's quads: each spans 1 / kEmbreeCurveQuads of the segment, and a curve leaves its
    // chord by at most (its parameter span)^2 / 8 times max |P''| <= 6 max |second differences|.
    const float secondDifference =
        std::max(length(p[0] - p[1] * 2.0f + p[2]), length(p[1] - p[2] * 2.0f + p[3]));
    const float embreeChord = 6.0f * secondDifference / (8.0f * float(kEmbreeCurveQuads * kEmbreeCurveQuads));
    const float tolerance = kCurveTestChord + embreeChord / radius;
    // The edge: |v| = 1, or for a ribbon |v| = |cos| of its normal with the ray.
    float edge = 1.0f;
    if (curves.type == CurveType::Ribbon)
        edge = std::abs(dot(curve::ribbonNormal(curves.normals[2 * shape.primitive],
                                                curves.normals[2 * shape.primitive + 1], u),
                            normalize(ray.direction)));
    if (std::abs(edge - std::abs(hit.v)) <= tolerance) return true;
    // Both tests see no curve nearer than twice its radius to the origin: near that distance,
    // their depths differ within their approximations.
    const float depth = hit.t * length(ray.direction);
    if (std::abs(depth - 2.0f * radius) <= (2.0f * tolerance) * radius + embreeChord) return true;
    // Their depths along the ray differ within the radius (a ray-facing surface's depth is its
    // centre line's; a quad's is interpolated): a hit that near the segment's end is one either way.
    if (std::isfinite(ray.tfar) &&
        (ray.tfar - hit.t) * length(ray.direction) <= (1.0f + tolerance) * radius + embreeChord)
        return true;
    // A ray nearly along the curve (within kCurveAlongDegrees of its tangent) sees Embree's quads
    // shorter than a few widths (kCurveForeshortening), turning with the foreshortened tangent.
    const Vec3f tangent = curve::bezierDerivative(p, u);
    const float sine =
        length(cross(tangent, ray.direction)) / (length(tangent) * length(ray.direction) + 1e-30f);
    const float projectedQuad = length(tangent) * sine / float(kEmbreeCurveQuads);
    if (sine <= std::sin(kCurveAlongDegrees * kPi / 180.0f) &&
        projectedQuad <= kCurveForeshortening * 2.0f * radius)
        return true;
    // Where pieces join, the two tests end them differently (ours at the perpendicular to the
    // tangent, Embree's at its quads' ends): within a piece's chord error of a segment's end.
    const float segmentLength = length(p[3] - p[0]) + 1e-30f;
    if (std::min(u, 1.0f - u) * segmentLength <= tolerance * radius + embreeChord) return true;
    if (other && scene_.shapeOf(*other).kind == ShapeKind::Curves) {
        const ShapeRef otherShape = scene_.shapeOf(*other);
        const float otherRadius =
            curve::bezier(scene_.curves[otherShape.index].controlRadii(otherShape.primitive),
                          std::clamp(other->u, 0.0f, 1.0f));
        const double depth = std::abs(double(hit.t) - double(other->t)) * double(length(ray.direction));
        if (depth <= 2.0 * (double(radius) + double(otherRadius)) * (1.0 + double(tolerance))) return true;
    }
    return false;
}

bool MismatchClassifier::isCutOutEdge(const Ray& ray, const Hit& hit) const {
    if (!isTriangleHit(scene_, hit)) return false;
    const ShapeRef shape = scene_.shapeOf(hit);
    const TriangleMesh& mesh = scene_.triangleMeshOf(shape);
    if (!mesh.alpha) return false;
    const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
    const uint64_t rayHash = cutOutRayHash(ray);
    auto keeps = [&](float b1, float b2) {
        return keepsCutOutHit(cutOutCoverage(*mesh.alpha, meshUvAt(mesh.uvs, index, b1, b2)), rayHash,
                              hit.geomId, hit.primId);
    };
    const bool kept = keeps(hit.u, hit.v);
    const float e = kEdgeTolerance;
    for (const auto& [d1, d2] : {std::pair{e, 0.0f}, {-e, 0.0f}, {0.0f, e}, {0.0f, -e}})
        if (keeps(hit.u + d1, hit.v + d2) != kept) return true;
    return false;
}

// A flat triangle cannot be hit again by a ray leaving it; a sphere can (from inside), but not
// within twice the origin's offset. A ray that does not leave its triangle, pointing back through
// its plane at a glancing angle, is not a self-intersection but a grazing hit: a shadow ray towards
// a light on the horizon (|cos| near 1e-7), whose side was chosen from the direction at the hit
// point and whose direction is taken from the moved origin, can start above the plane and end
// below it. A ray crossing its plane at a larger angle still is one (a wrong side is a bug).
bool MismatchClassifier::isSelfIntersection(const CrosscheckRay& cray, const BackendAnswer& answer) const {
    if (!cray.leavesSurface || !answer.hasHit) return false;
    const Hit& hit = answer.hit;
    if (hit.geomId != cray.sourceGeomId || hit.primId != cray.sourcePrimId) return false;
    if (isTriangleHit(scene_, hit)) return !crossesItsTriangleAtAGlance(cray.ray, hit);
    return double(hit.t) * double(length(cray.ray.direction)) <= 2.0 * double(cray.sourceDistance);
}

// Whether the ray starts on one side of the plane of triangle `hit` and points to the other, at a
// glancing angle (|cos| < kGrazingCosine). In double, in the triangle's own space: the offset puts
// the origin at least a float ulp off the plane, far beyond double's rounding.
bool MismatchClassifier::crossesItsTriangleAtAGlance(const Ray& ray, const Hit& hit) const {
    const ShapeRef shape = scene_.shapeOf(hit);
    const TriangleMesh& mesh = scene_.triangleMeshOf(shape);
    if (mesh.moves()) return false;
    detail::ObjectSpaceRay objectRay{ray.origin, ray.direction};
    if (shape.kind == ShapeKind::Instance)
        objectRay = detail::toObjectSpace(scene_.toWorldOf(shape, ray.time), ray);
    using V = std::array<double, 3>;
    const auto point = [&](int k) {
        const Vec3f p = mesh.positions[mesh.indices[3 * size_t(shape.primitive) + k]];
        return V{p.x, p.y, p.z};
    };
    const auto minus = [](const V& a, const V& b) { return V{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    const auto dotD = [](const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const V p0 = point(0), e1 = minus(point(1), p0), e2 = minus(point(2), p0);
    const V n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const V origin{objectRay.origin.x, objectRay.origin.y, objectRay.origin.z};
    const V direction{objectRay.direction.x, objectRay.direction.y, objectRay.direction.z};
    const double side = dotD(minus(origin, p0), n), along = dotD(direction, n);
    const double cosine = std::abs(along) / std::sqrt(dotD(n, n) * dotD(direction, direction));
    return side * along < 0.0 && cosine < double(kGrazingCosine);
}

// Our triangle test rejects hits within its error bound on t of the origin (geometry/
// triangle.h): there rounding cannot tell whether the ray starts before or after the surface.
bool MismatchClassifier::withinTriangleTestError(const Ray& ray, const Hit& hit) const {
    if (!isTriangleHit(scene_, hit)) return false;
    const ShapeRef shape = scene_.shapeOf(hit);
    const TriangleMesh& mesh = scene_.triangleMeshOf(shape);
    if (mesh.moves()) return false;
    float vertices[9];
    for (int k = 0; k < 3; ++k) {
        const Vec3f p = mesh.positions[mesh.indices[3 * size_t(shape.primitive) + k]];
        for (int axis = 0; axis < 3; ++axis) vertices[3 * k + axis] = p[axis];
    }
    // An instance's triangle is tested in its prototype's space, as both backends test it.
    detail::ObjectSpaceRay objectRay{ray.origin, ray.direction};
    if (shape.kind == ShapeKind::Instance)
        objectRay = detail::toObjectSpace(scene_.toWorldOf(shape, ray.time), ray);
    return hit.t - ray.tnear <=
           watertightTErrorBound(WatertightRay(objectRay.origin, objectRay.direction), vertices);
}

MismatchKind MismatchClassifier::classify(const CrosscheckRay& cray, const BackendAnswer& ours,
                                          const BackendAnswer& embree) const {
    const Ray& ray = cray.ray;
    if (isSelfIntersection(cray, ours) || isSelfIntersection(cray, embree))
        return MismatchKind::SelfIntersection;
    if (ours.hitSomething && embree.hitSomething && !cray.isSegment()) {
        const Hit& a = ours.hit;
        const Hit& b = embree.hit;
        if (sameDistance(ray, a.t, b.t))
            return isNearEdge(scene_, a) || isNearEdge(scene_, b) ? MismatchKind::EdgeOrVertex
                                                                  : MismatchKind::Tie;
        // One backend missed the nearer surface: why?
        if (isCurveApproximation(ray, a.t < b.t ? a : b, a.t < b.t ? &b : &a))
            return MismatchKind::CurveApproximation;
        return explainHit(ray, a.t < b.t ? a : b).value_or(MismatchKind::Unexplained);
    }
    // One backend found something the other did not.
    const BackendAnswer& found = ours.hitSomething ? ours : embree;
    if (!found.hasHit) return MismatchKind::Unexplained;  // blocked, yet intersect() finds nothing
    return explainHit(ray, found.hit).value_or(MismatchKind::Unexplained);
}

CrosscheckReport compareBackends(const Scene& scene, const BvhAccelerator& ours,
                                 const EmbreeAccelerator& embree, const std::vector<CrosscheckRay>& rays,
                                 const CrosscheckOptions& options) {
    CrosscheckReport report;
    report.scene = scene.sourcePath.string();
    report.seed = options.seed;
    report.rayCount = rays.size();
    const MismatchClassifier classifier(scene);
    std::vector<Mismatch> unexplained, explained;
    double relativeSum = 0.0, pointSum = 0.0;
    for (const CrosscheckRay& r : rays) {
        BackendAnswer a, b;
        bool agree;
        // As the integrator traces it: a ray leaving a triangle names it.
        const TriangleLeft left = triangleLeft(scene, r);
        if (r.isSegment()) {
            a.hitSomething = ours.occluded(r.ray, left);
            b.hitSomething = embree.occluded(r.ray, left);
            agree = a.hitSomething == b.hitSomething;
            if (!agree) {
                // The closest blocker of the backend that saw one, to classify the disagreement.
                if (a.hitSomething) a.hasHit = ours.intersect(r.ray, a.hit, left);
                if (b.hitSomething) b.hasHit = embree.intersect(r.ray, b.hit, left);
            }
        } else {
            a.hitSomething = a.hasHit = ours.intersect(r.ray, a.hit, left);
            b.hitSomething = b.hasHit = embree.intersect(r.ray, b.hit, left);
            agree = a.hitSomething == b.hitSomething && (!a.hitSomething || samePrimitive(a.hit, b.hit));
            if (agree && a.hitSomething) {
                const double relative = relativeDifference(a.hit.t, b.hit.t);
                const double point = classifier.pointDistance(r.ray, a.hit.t, b.hit.t);
                report.maxRelativeDistance = std::max(report.maxRelativeDistance, relative);
                report.maxPointDistance = std::max(report.maxPointDistance, point);
                relativeSum += relative;
                pointSum += point;
                ++report.samePrimitiveHits;
            }
        }
        CrosscheckKindStats& kindStats = report.byKind[size_t(r.kind)];
        ++kindStats.rays;
        if (agree) {
            ++kindStats.agreements;
            ++report.agreements;
            continue;
        }
        if (a.hitSomething != b.hitSomething) {
            ++kindStats.hitMissDisagreements;
            ++report.hitMissDisagreements;
        } else {
            ++kindStats.primitiveDisagreements;
            ++report.primitiveDisagreements;
        }
        Mismatch m{r, a, b, classifier.classify(r, a, b)};
        ++report.mismatchesByKind[size_t(m.kind)];
        const bool failure = m.kind == MismatchKind::Unexplained || m.kind == MismatchKind::SelfIntersection;
        std::vector<Mismatch>& kept = failure ? unexplained : explained;
        if (kept.size() < options.keptMismatches) kept.push_back(m);
    }
    if (report.samePrimitiveHits > 0) {
        report.meanRelativeDistance = relativeSum / double(report.samePrimitiveHits);
        report.meanPointDistance = pointSum / double(report.samePrimitiveHits);
    }
    report.mismatches = std::move(unexplained);
    for (const Mismatch& m : explained)
        if (report.mismatches.size() < options.keptMismatches) report.mismatches.push_back(m);

    if (options.measureThroughput) {
        // Alternate the backends and keep each one's best of two runs, to damp noise.
        for (int round = 0; round < 2; ++round) {
            report.oursRaysPerSecond = std::max(report.oursRaysPerSecond, measureRaysPerSecond(ours, rays));
            report.embreeRaysPerSecond =
                std::max(report.embreeRaysPerSecond, measureRaysPerSecond(embree, rays));
        }
    }
    return report;
}

CrosscheckReport runCrosscheck(const Scene& scene, const CrosscheckOptions& options) {
    auto start = Clock::now();
    const EmbreeAccelerator embree(scene);
    const double embreeBuild = std::chrono::duration<double>(Clock::now() - start).count();
    start = Clock::now();
    const BvhAccelerator ours(scene);
    const double oursBuild = std::chrono::duration<double>(Clock::now() - start).count();
    const std::vector<CrosscheckRay> rays = generateCrosscheckRays(scene, embree, options);
    CrosscheckReport report = compareBackends(scene, ours, embree, rays, options);
    report.embreeBuildSeconds = embreeBuild;
    report.oursBuildSeconds = oursBuild;
    return report;
}

std::string formatCrosscheckText(const CrosscheckReport& report, size_t maxListed) {
    std::string out;
    out += fmt::format("crosscheck {}: {} rays (seed {}), bvh against embree\n", report.scene,
                       report.rayCount, report.seed);
    out += fmt::format("  {:<8} {:>10} {:>10} {:>9} {:>10}\n", "rays", "count", "agree", "hit/miss",
                       "other prim");
    for (int k = 0; k < kCrosscheckRayKindCount; ++k) {
        const CrosscheckKindStats& s = report.byKind[k];
        out +=
            fmt::format("  {:<8} {:>10} {:>10} {:>9} {:>10}\n", crosscheckRayKindName(CrosscheckRayKind(k)),
                        s.rays, s.agreements, s.hitMissDisagreements, s.primitiveDisagreements);
    }
    out += fmt::format(
        "  agreement {:.5f}% ({} of {}), {:.5f}% counting ties; hit/miss disagreements {}, "
        "different primitive {}\n",
        100.0 * report.agreementRatio(), report.agreements, report.rayCount,
        100.0 * report.agreementRatioCountingTies(), report.hitMissDisagreements,
        report.primitiveDisagreements);
    out += fmt::format(
        "  distance on the same primitive ({} hits): relative difference of t max {:.3g}, mean {:.3g}; "
        "hit points apart by at most {:.3g}, on average {:.3g} of the scene's coordinate magnitude\n",
        report.samePrimitiveHits, report.maxRelativeDistance, report.meanRelativeDistance,
        report.maxPointDistance, report.meanPointDistance);
    out += "  mismatches:";
    for (int k = 0; k < kMismatchKindCount; ++k)
        out += fmt::format("{} {} {}", k ? "," : "", mismatchKindName(MismatchKind(k)),
                           report.mismatchesByKind[k]);
    out += "\n";
    if (report.oursRaysPerSecond > 0.0 && report.embreeRaysPerSecond > 0.0)
        out += fmt::format(
            "  throughput (1 thread, same rays): bvh {:.2f} M rays/s, embree {:.2f} M rays/s, "
            "bvh/embree {:.2f}\n",
            report.oursRaysPerSecond * 1e-6, report.embreeRaysPerSecond * 1e-6,
            report.oursRaysPerSecond / report.embreeRaysPerSecond);
    if (report.oursBuildSeconds > 0.0 || report.embreeBuildSeconds > 0.0)
        out += fmt::format("  build: bvh {:.3f} s, embree {:.3f} s\n", report.oursBuildSeconds,
                           report.embreeBuildSeconds);

    const size_t listed = std::min(maxListed, report.mismatches.size());
    if (listed > 0) {
        out +=
            fmt::format("mismatching rays (origin, direction, tnear, tfar as %a floats; first {} of {}):\n",
                        listed, report.hitMissDisagreements + report.primitiveDisagreements);
        for (size_t i = 0; i < listed; ++i) {
            const Mismatch& m = report.mismatches[i];
            const Ray& r = m.ray.ray;
            out += fmt::format(
                "  [{}] {} ray {} ({}): origin ({}, {}, {}) direction ({}, {}, {}) tnear {} tfar {} time "
                "{}\n",
                mismatchKindName(m.kind), crosscheckRayKindName(m.ray.kind), m.ray.index,
                m.ray.isSegment() ? "occluded" : "intersect", hexFloat(r.origin.x), hexFloat(r.origin.y),
                hexFloat(r.origin.z), hexFloat(r.direction.x), hexFloat(r.direction.y),
                hexFloat(r.direction.z), hexFloat(r.tnear), hexFloat(r.tfar), hexFloat(r.time));
            out += fmt::format("      bvh: {}\n      embree: {}\n", describeAnswer(m.ray, m.ours),
                               describeAnswer(m.ray, m.embree));
        }
    }
    return out;
}

std::string formatCrosscheckJson(const CrosscheckReport& report, size_t maxListed) {
    using nlohmann::json;
    json j;
    j["scene"] = report.scene;
    j["seed"] = report.seed;
    j["rays"] = report.rayCount;
    j["agreements"] = report.agreements;
    j["agreementRatio"] = report.agreementRatio();
    j["agreementRatioCountingTies"] = report.agreementRatioCountingTies();
    j["hitMissDisagreements"] = report.hitMissDisagreements;
    j["primitiveDisagreements"] = report.primitiveDisagreements;
    json kinds = json::object();
    for (int k = 0; k < kCrosscheckRayKindCount; ++k) {
        const CrosscheckKindStats& s = report.byKind[k];
        kinds[crosscheckRayKindName(CrosscheckRayKind(k))] = {
            {"rays", s.rays},
            {"agreements", s.agreements},
            {"hitMissDisagreements", s.hitMissDisagreements},
            {"primitiveDisagreements", s.primitiveDisagreements}};
    }
    j["byKind"] = kinds;
    j["distance"] = {{"samePrimitiveHits", report.samePrimitiveHits},
                     {"maxRelativeDifference", report.maxRelativeDistance},
                     {"meanRelativeDifference", report.meanRelativeDistance},
                     {"maxPointDistance", report.maxPointDistance},
                     {"meanPointDistance", report.meanPointDistance}};
    json byKind = json::object();
    for (int k = 0; k < kMismatchKindCount; ++k)
        byKind[mismatchKindName(MismatchKind(k))] = report.mismatchesByKind[k];
    j["mismatches"] = byKind;
    j["unexplained"] = report.unexplained();
    j["selfIntersections"] = report.selfIntersections();
    j["throughput"] = {
        {"bvhRaysPerSecond", report.oursRaysPerSecond},
        {"embreeRaysPerSecond", report.embreeRaysPerSecond},
        {"ratio",
         report.embreeRaysPerSecond > 0.0 ? report.oursRaysPerSecond / report.embreeRaysPerSecond : 0.0}};
    j["buildSeconds"] = {{"bvh", report.oursBuildSeconds}, {"embree", report.embreeBuildSeconds}};
    j["tolerances"] = {
        {"edge", kEdgeTolerance}, {"distance", kDistanceTolerance}, {"grazingCosine", kGrazingCosine}};
    json list = json::array();
    for (size_t i = 0; i < std::min(maxListed, report.mismatches.size()); ++i) {
        const Mismatch& m = report.mismatches[i];
        auto answer = [&](const BackendAnswer& a) {
            json x = {{"hit", a.hitSomething}};
            if (a.hasHit)
                x["closest"] = {{"geomId", a.hit.geomId},
                                {"primId", a.hit.primId},
                                {"t", hexFloat(a.hit.t)},
                                {"u", hexFloat(a.hit.u)},
                                {"v", hexFloat(a.hit.v)}};
            return x;
        };
        const Ray& r = m.ray.ray;
        list.push_back(
            {{"kind", mismatchKindName(m.kind)},
             {"rayKind", crosscheckRayKindName(m.ray.kind)},
             {"index", m.ray.index},
             {"call", m.ray.isSegment() ? "occluded" : "intersect"},
             {"origin", {hexFloat(r.origin.x), hexFloat(r.origin.y), hexFloat(r.origin.z)}},
             {"direction", {hexFloat(r.direction.x), hexFloat(r.direction.y), hexFloat(r.direction.z)}},
             {"tnear", hexFloat(r.tnear)},
             {"tfar", hexFloat(r.tfar)},
             {"time", hexFloat(r.time)},
             {"bvh", answer(m.ours)},
             {"embree", answer(m.embree)}});
    }
    j["listedMismatches"] = list;
    return j.dump(2) + "\n";
}

int runCrosscheckCommand(const std::string& scenePath, const std::string& patch,
                         const CrosscheckOptions& options, bool json) {
    SceneFileOptions sceneOptions;
    sceneOptions.patch = patch;
    const Scene scene = loadSceneFile(scenePath, sceneOptions);
    const CrosscheckReport report = runCrosscheck(scene, options);
    const std::string text = json ? formatCrosscheckJson(report) : formatCrosscheckText(report);
    std::fwrite(text.data(), 1, text.size(), stdout);
    if (report.failures() > 0) {
        std::fprintf(
            stderr,
            "penumbra: crosscheck: %llu unexplained mismatches and %llu self-intersections between bvh "
            "and embree\n",
            (unsigned long long)report.unexplained(), (unsigned long long)report.selfIntersections());
        return kCrosscheckFailed;
    }
    return 0;
}

}  // namespace penumbra
