// A shading point rebuilt from a backend's hit. This is shared by all backends so that they
// shade identically: positions come from our own vertex data and barycentrics (or, for spheres,
// the hit reprojected onto the surface), not from origin + t * direction.
#pragma once

#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/check.h"
#include "core/float_error.h"
#include "core/frame.h"
#include "core/motion.h"
#include "core/ray.h"
#include "core/sampling.h"
#include "core/simd.h"
#include "geometry/face_frames.h"
#include "geometry/hit.h"
#include "geometry/scene_geometry.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace penumbra {

struct SurfaceInteraction {
    Vec3f position;
    Vec3f positionError;    // bound on each coordinate's absolute error (core/ray_offset.h)
    Vec3f geometricNormal;  // unit, on the shape's front side
    Vec3f shadingNormal;    // unit, in the hemisphere of geometricNormal
    Vec2f uv;
    uint32_t material = 0;
    ShapeRef shape;  // the shape and primitive hit (SceneGeometry::shapeOf)
    // Frame::fromNormal(shadingNormal) computed beforehand (FaceFrames), when there is one: for a
    // still, non-degenerate triangle whose shading normal is its geometric normal. Null otherwise.
    const Frame* shadingFrame = nullptr;
};

namespace detail {

inline Vec3f vertexAt(const TriangleMesh& mesh, uint32_t vertex, float time) {
    return mesh.deforms() ? interpolateKeys(mesh.positionKeys, vertex, time) : mesh.positions[vertex];
}

// The ray in a shape's object space, as both backends trace it there (accel/bvh_accelerator.h,
// Embree's instances) and as hits are recomputed: the direction is not normalized, so t is the
// same in both spaces.
struct ObjectSpaceRay {
    Vec3f origin, direction;
};
inline ObjectSpaceRay toObjectSpace(const Transform& toWorld, const Ray& ray) {
    const Transform toObject = toWorld.inverse();
    return {toObject.applyPoint(ray.origin), toObject.applyVector(ray.direction)};
}

// Moves a point and its normals from object to world space for a moving shape or an instance:
// the position as a point, the normals by the inverse transpose (renormalized; a mirroring
// transform keeps them on the side they were on). A shading frame computed beforehand is in object
// space, so it is dropped: the integrator builds the world one from the shading normal.
// The error bound grows by the transform's own rounding (pbrt-v4, section 6.8.5), and by what
// the backends' way back costs: they test a ray leaving the point in object space, its origin
// taken there by the stored inverse, which rounds (gamma(3) of its terms) and is not the exact
// inverse (inverse * matrix differs from the identity by a few ulps, times the ratio of the
// scales for an uneven scale). Both are bounded in object space and mapped to the world by
// |matrix|, so that the offset origin lies on its side of the surface the backend tests.
inline void placeInWorld(const Transform& toWorld, SurfaceInteraction& si) {
    si.shadingFrame = nullptr;
    const auto& m = toWorld.matrix().m;
    const auto& inv = toWorld.inverseMatrix().m;
    const Vec3f q = abs(si.position), e = si.positionError;
    const Vec3f world = toWorld.applyPoint(si.position), p = abs(world);
    float wayBack[3];  // object space
    for (int row = 0; row < 3; ++row) {
        // inverse * matrix - identity, exactly enough in double (products of floats are exact).
        double drift = 0.0;
        for (int column = 0; column < 4; ++column) {
            double f = column == 3 ? double(inv[row][3]) : row == column ? -1.0 : 0.0;
            for (int k = 0; k < 3; ++k) f += double(inv[row][k]) * double(m[k][column]);
            drift += std::abs(f) * (column == 3 ? 1.0 : double(q[column]));
        }
        const float rounding = std::abs(inv[row][0]) * p.x + std::abs(inv[row][1]) * p.y +
                               std::abs(inv[row][2]) * p.z + std::abs(inv[row][3]);
        wayBack[row] = float(drift) * (1.0f + gamma(2)) + gamma(3) * rounding;
    }
    for (int row = 0; row < 3; ++row) {
        const auto& r = m[row];
        const float absSum =
            std::abs(r[0]) * q.x + std::abs(r[1]) * q.y + std::abs(r[2]) * q.z + std::abs(r[3]);
        const float propagated = std::abs(r[0]) * e.x + std::abs(r[1]) * e.y + std::abs(r[2]) * e.z;
        const float back =
            std::abs(r[0]) * wayBack[0] + std::abs(r[1]) * wayBack[1] + std::abs(r[2]) * wayBack[2];
        si.positionError[row] = (gamma(3) * absSum + propagated + back) * (1.0f + gamma(3));
    }
    si.position = world;
    si.geometricNormal = normalize(toWorld.applyNormal(si.geometricNormal));
    si.shadingNormal = faceForward(normalize(toWorld.applyNormal(si.shadingNormal)), si.geometricNormal);
}

// Replaces the hit's t and barycentrics with those of our watertight test on triangle (p0, p1, p2),
// unless that test misses it (a ray along an edge), when the backend's values stay.
inline void recomputeTriangleHit(Vec3f origin, Vec3f direction, Vec3f p0, Vec3f p1, Vec3f p2, const Ray& ray,
                                 Hit& hit) {
    const float vertices[9] = {p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, p2.x, p2.y, p2.z};
    TriangleHit th;
    if (intersectTriangleWatertight(WatertightRay(origin, direction), vertices, ray.tnear, ray.tfar, th)) {
        hit.t = th.t;
        hit.u = th.b1;
        hit.v = th.b2;
    }
}

// si.position = p0 b0 + p1 b1 + p2 b2 and si.positionError = (|p0 b0| + |p1 b1| + |p2 b2|) gamma(7)
// (b0 = 1 - b1 - b2 with two roundings, then three products and two sums: pbrt-v4's bound), the
// three coordinates at once in SSE lanes: the same operations in the same order as Vec3f's, so
// the same bits, in fewer instructions (bench/README.md, "Speed tricks").
[[gnu::always_inline]] inline void setBarycentricPoint(Vec3f p0, Vec3f p1, Vec3f p2, float b0, float b1,
                                                       float b2, SurfaceInteraction& si) {
    const __m128 t0 = _mm_mul_ps(toLanes(p0), _mm_set1_ps(b0));
    const __m128 t1 = _mm_mul_ps(toLanes(p1), _mm_set1_ps(b1));
    const __m128 t2 = _mm_mul_ps(toLanes(p2), _mm_set1_ps(b2));
    const __m128 position = _mm_add_ps(_mm_add_ps(t0, t1), t2);
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 error = _mm_mul_ps(
        _mm_add_ps(_mm_add_ps(_mm_andnot_ps(sign, t0), _mm_andnot_ps(sign, t1)), _mm_andnot_ps(sign, t2)),
        _mm_set1_ps(gamma(7)));
    si.position = toVec3f(position);
    si.positionError = toVec3f(error);
}

// The shading point at the hit's barycentrics on triangle (p0, p1, p2) of `mesh` (`index`: its three
// vertex indices), in the mesh's own space; the caller places it in the world for moving meshes.
// `faceFrame`, when given, is the triangle's frame computed beforehand (FaceFrames): its n is the
// triangle's triangleNormal(). False for a degenerate triangle, which has no normal: the caller
// then turns both normals towards the ray. Always inline: out of line, its call and its vectors
// passed through memory cost more than it does.
[[gnu::always_inline]] inline bool triangleInteraction(const TriangleMesh& mesh, const uint32_t* index,
                                                       Vec3f p0, Vec3f p1, Vec3f p2, const Hit& hit,
                                                       SurfaceInteraction& si,
                                                       const Frame* faceFrame = nullptr) {
    const float b1 = hit.u, b2 = hit.v, b0 = 1.0f - b1 - b2;
    setBarycentricPoint(p0, p1, p2, b0, b1, b2, si);
    si.geometricNormal = faceFrame ? faceFrame->n : triangleNormal(p0, p1, p2);
    const bool hasNormal = si.geometricNormal != Vec3f{0.0f, 0.0f, 0.0f};
    if (!hasNormal) si.geometricNormal = {0.0f, 0.0f, 1.0f};
    si.shadingNormal = si.geometricNormal;
    if (hasNormal) si.shadingFrame = faceFrame;
    // Vertex normals are only used for meshes that do not deform (they would need keys too).
    if (!mesh.normals.empty() && !mesh.deforms()) {
        const Vec3f ns =
            mesh.normals[index[0]] * b0 + mesh.normals[index[1]] * b1 + mesh.normals[index[2]] * b2;
        const float nsLength = length(ns);
        if (nsLength > 0.0f) {
            si.shadingNormal = faceForward(ns / nsLength, si.geometricNormal);
            si.shadingFrame = nullptr;
        }
    }
    PENUMBRA_CHECK(!(dot(si.shadingNormal, si.geometricNormal) < 0.0f),
                   "the shading normal lies in the geometric normal's hemisphere");
    if (!mesh.uvs.empty()) si.uv = meshUvAt(mesh.uvs, index, b1, b2);
    si.material = mesh.material;
    return hasNormal;
}

// Object to world at the ray's time of a shape in a space of its own (a moving mesh or sphere, an
// instance); empty for shapes in world space.
inline std::optional<Transform> placementOf(const SceneGeometry& scene, ShapeRef shape, float time) {
    if (!scene.inObjectSpace(shape)) return std::nullopt;
    return scene.toWorldOf(shape, time);
}

// canonicalizeHit on `shape`, placed by `toWorld` (placementOf).
inline void canonicalizeShapeHit(const SceneGeometry& scene, ShapeRef shape,
                                 const std::optional<Transform>& toWorld, const Ray& ray, Hit& hit) {
    // Into object space exactly as the BVH takes a ray into an instance.
    const ObjectSpaceRay objectRay =
        toWorld ? toObjectSpace(*toWorld, ray) : ObjectSpaceRay{ray.origin, ray.direction};
    if (shape.kind == ShapeKind::Curves) {
        CurveHit curveHit;
        if (intersectCurveSegment(scene.curves[shape.index], shape.primitive, objectRay.origin,
                                  objectRay.direction, ray.tnear, ray.tfar, curveHit)) {
            hit.t = curveHit.t;
            hit.u = curveHit.u;
            hit.v = curveHit.v;
        }
    } else if (shape.kind == ShapeKind::BilinearPatches) {
        // Both backends' hits come from intersectBilinearPatch on the same ray (Embree's from our
        // user geometry): they are canonical already.
    } else if (shape.kind != ShapeKind::Sphere) {
        const TriangleMesh& mesh = scene.triangleMeshOf(shape);
        const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
        recomputeTriangleHit(objectRay.origin, objectRay.direction, vertexAt(mesh, index[0], ray.time),
                             vertexAt(mesh, index[1], ray.time), vertexAt(mesh, index[2], ray.time), ray,
                             hit);
    } else {
        const Sphere& sphere = scene.spheres[shape.index];
        float t;
        if (intersectSphere(objectRay.origin, objectRay.direction, sphere.center, sphere.radius, ray.tnear,
                            ray.tfar, t))
            hit.t = t;
    }
}

}  // namespace detail

// The same hit whichever backend found it: t and the barycentrics of the primitive the backend
// reports are recomputed with the tests our BVH uses (geometry/triangle.h, sphere.h; moving
// shapes and instances in object space, as the BVH traverses them), so that whenever Embree and the BVH find
// the same primitive everything downstream sees the same bits, and renders with either backend are
// bit-identical unless some hit differs. Embree rounds differently (its Plücker-form test); should
// our test miss the primitive (a ray along an edge), the backend's values stay.
inline void canonicalizeHit(const SceneGeometry& scene, const Ray& ray, Hit& hit) {
    const ShapeRef shape = scene.shapeOf(hit);
    detail::canonicalizeShapeHit(scene, shape, detail::placementOf(scene, shape, ray.time), ray, hit);
}

namespace detail {

// The shading point on triangle `shape.primitive` of an instance's prototype, placed in the world;
// `faceFrames`, when given, supplies the prototype triangle's normal (the same bits as computing it).
// Out of line: inlined into the integrator, it costs scenes without instances registers.
[[gnu::noinline]] inline SurfaceInteraction instanceInteraction(const SceneGeometry& scene, ShapeRef shape,
                                                                const Transform& toWorld, const Ray& ray,
                                                                const Hit& hit,
                                                                const FaceFrames* faceFrames) {
    const MeshInstance& instance = scene.instances[shape.index];
    const TriangleMesh& mesh = scene.prototypes[instance.prototype];
    const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
    SurfaceInteraction si;
    si.shape = shape;
    const Frame* faceFrame =
        faceFrames ? faceFrames->findPrototype(instance.prototype, shape.primitive) : nullptr;
    const bool hasNormal =
        triangleInteraction(mesh, index, mesh.positions[index[0]], mesh.positions[index[1]],
                            mesh.positions[index[2]], hit, si, faceFrame);
    placeInWorld(toWorld, si);  // its error bound covers the way back into the instance's space
    si.material = instance.material;
    if (!hasNormal) si.geometricNormal = si.shadingNormal = normalize(-ray.direction);
    return si;
}

// The shading point on segment `shape.primitive` of a curve set: the ray's point at the hit (t is
// canonical, so both backends give the same bits), a geometric normal across the curve facing the
// ray (a ribbon's own, turned to the ray), and uv = (u along the curve, v across it in [0, 1], as
// pbrt-v4's). A cylinder's shading normal turns from the geometric one towards the side
// of the hit by |v| times 90 degrees (pbrt-v4's). Its error bound is pbrt-v4's, twice the width:
// the hit lies on an approximation of the surface within a fraction of its width.
[[gnu::noinline]] inline SurfaceInteraction curveInteraction(const SceneGeometry& scene, ShapeRef shape,
                                                             const Ray& ray, const Hit& hit) {
    const Curves& curves = scene.curves[shape.index];
    const size_t segment = shape.primitive;
    const float u = std::clamp(hit.u, 0.0f, 1.0f);
    float v = hit.v;
    const Vec3f centre = curve::bezier(curves.controlPoints(segment), u);
    const float radius = curve::bezier(curves.controlRadii(segment), u);
    const Vec3f towardsRay = normalize(-ray.direction);
    Vec3f tangent = curve::bezierDerivative(curves.controlPoints(segment), u);
    const float tangentLength = length(tangent);
    tangent = tangentLength > 0.0f ? tangent / tangentLength : Frame::fromNormal(towardsRay).s;
    Vec3f normal;
    if (curves.type == CurveType::Ribbon) {
        normal = curve::ribbonNormal(curves.normals[2 * segment], curves.normals[2 * segment + 1], u);
        // Across the ribbon as it is: its visible half width is the radius times |cos|.
        v /= std::max(std::abs(dot(normal, towardsRay)), 1e-6f);
        normal = normalize(normal - tangent * dot(normal, tangent));
    } else {
        normal = towardsRay - tangent * dot(towardsRay, tangent);
    }
    v = std::clamp(v, -1.0f, 1.0f);
    const float normalLength = length(normal);
    normal = normalLength > 0.0f && std::isfinite(normalLength) ? normal / normalLength
                                                                : Frame::fromNormal(tangent).s;
    normal = faceForward(normal, towardsRay);
    SurfaceInteraction si;
    si.shape = shape;
    si.position = ray.at(hit.t);
    const float width = 2.0f * std::abs(radius);
    si.positionError = Vec3f{1.0f, 1.0f, 1.0f} * (2.0f * width) + abs(si.position) * gamma(4);
    si.geometricNormal = normal;
    si.shadingNormal = normal;
    if (curves.type == CurveType::Cylinder) {
        // Across the curve, towards the side the ray passed on.
        Vec3f across = cross(tangent, normal);
        if (dot(si.position - centre, across) < 0.0f) across = -across;
        const float angle = std::abs(v) * (0.5f * kPi);
        si.shadingNormal = normalize(normal * std::cos(angle) + across * std::sin(angle));
    }
    const Vec2f uRange = curves.uRanges[segment];
    si.uv = {uRange.x + (uRange.y - uRange.x) * u, 0.5f * (v + 1.0f)};
    si.material = curves.material;
    return si;
}

// The shading point on patch `shape.primitive` of a bilinear patch set: the patch's own point at
// the hit's (u, v) (not the ray's, so the error bound is the interpolation's), the geometric normal
// cross(dp/du, dp/dv) turned to the front (geometry/bilinear_patches.h), the vertex normals and uvs
// interpolated bilinearly (pbrt-v4's BilinearPatch::InteractionFromIntersection).
[[gnu::noinline]] inline SurfaceInteraction patchInteraction(const SceneGeometry& scene, ShapeRef shape,
                                                             const Ray& ray, const Hit& hit) {
    const BilinearPatches& patches = scene.patches[shape.index];
    const std::array<Vec3f, 4> p = patches.cornerPositions(shape.primitive);
    const float u = std::clamp(hit.u, 0.0f, 1.0f), v = std::clamp(hit.v, 0.0f, 1.0f);
    SurfaceInteraction si;
    si.shape = shape;
    si.position = bilinear::point(p.data(), u, v);
    si.positionError = bilinear::pointError(p.data());
    Vec3f normal = cross(bilinear::dpdu(p.data(), v), bilinear::dpdv(p.data(), u));
    const float normalLength = length(normal);
    const bool hasNormal = normalLength > 0.0f && std::isfinite(normalLength);
    normal = hasNormal ? normal / normalLength : normalize(-ray.direction);
    const uint32_t* corner = &patches.indices[4 * size_t(shape.primitive)];
    Vec3f shading = normal;
    if (!patches.normals.empty()) {
        const auto at = [&](int k) { return patches.normals[corner[k]]; };
        const Vec3f ns = bilinear::lerp(v, bilinear::lerp(u, at(0), at(1)), bilinear::lerp(u, at(2), at(3)));
        const float nsLength = length(ns);
        if (nsLength > 0.0f && std::isfinite(nsLength)) {
            shading = ns / nsLength;
            normal = faceForward(normal, shading);
        }
    } else if (patches.reversed && hasNormal) {
        normal = -normal;
    }
    si.geometricNormal = normal;
    si.shadingNormal = faceForward(shading, normal);
    if (!patches.uvs.empty()) {
        const auto at = [&](int k) { return patches.uvs[corner[k]]; };
        si.uv = bilinear::lerp(v, bilinear::lerp(u, at(0), at(1)), bilinear::lerp(u, at(2), at(3)));
    } else {
        si.uv = {u, v};
    }
    si.material = patches.material;
    return si;
}

// The parameter along its segment of a curve hit whose uv.x is the curve's u.
inline float curveSegmentU(const Curves& curves, uint32_t segment, float curveU) {
    const Vec2f range = curves.uRanges[segment];
    return range.y > range.x ? std::clamp((curveU - range.x) / (range.y - range.x), 0.0f, 1.0f) : 0.0f;
}

}  // namespace detail

// The unit tangent of the curve at a curve's shading point (its fiber direction), perpendicular to
// its shading normal. Recomputed from the segment when asked rather than kept in every
// SurfaceInteraction: a field more there cost every other shape's hits 3.1% of the path loop's
// instructions, recomputing it 0.7% (bench/README.md, "Speed tricks").
[[gnu::noinline]] inline Vec3f curveTangent(const SceneGeometry& scene, const SurfaceInteraction& si) {
    const Curves& curves = scene.curves[si.shape.index];
    const Vec3f* p = curves.controlPoints(si.shape.primitive);
    Vec3f tangent = curve::bezierDerivative(p, detail::curveSegmentU(curves, si.shape.primitive, si.uv.x));
    tangent = tangent - si.shadingNormal * dot(tangent, si.shadingNormal);
    const float tangentLength = length(tangent);
    return tangentLength > 0.0f && std::isfinite(tangentLength) ? tangent / tangentLength
                                                                : Frame::fromNormal(si.shadingNormal).s;
}

// The shading frame at a curve's shading point: the fiber's tangent as its first axis.
[[gnu::noinline]] inline Frame curveShadingFrame(const SceneGeometry& scene, const SurfaceInteraction& si) {
    return Frame::fromXZ(curveTangent(scene, si), si.shadingNormal);
}

namespace detail {

// makeSurfaceInteraction on `shape`, placed by `toWorld` (placementOf).
inline SurfaceInteraction shapeInteraction(const SceneGeometry& scene, ShapeRef shape,
                                           const std::optional<Transform>& toWorld, const Ray& ray,
                                           const Hit& hit, const FaceFrames* faceFrames) {
    SurfaceInteraction si;
    si.shape = shape;
    if (shape.kind == ShapeKind::Instance)
        return instanceInteraction(scene, shape, *toWorld, ray, hit, faceFrames);
    if (shape.kind == ShapeKind::Curves) return curveInteraction(scene, shape, ray, hit);
    if (shape.kind == ShapeKind::BilinearPatches) return patchInteraction(scene, shape, ray, hit);
    if (shape.kind == ShapeKind::Mesh) {
        const TriangleMesh& mesh = scene.meshes[shape.index];
        const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
        const bool hasNormal = triangleInteraction(mesh, index, vertexAt(mesh, index[0], ray.time),
                                                   vertexAt(mesh, index[1], ray.time),
                                                   vertexAt(mesh, index[2], ray.time), hit, si);
        if (toWorld) placeInWorld(*toWorld, si);
        if (!hasNormal) si.geometricNormal = si.shadingNormal = normalize(-ray.direction);
    } else {
        const Sphere& sphere = scene.spheres[shape.index];
        // The hit point, reprojected onto the sphere in the sphere's own space.
        Vec3f hitPoint = ray.at(hit.t);
        if (toWorld) hitPoint = toWorld->inverse().applyPoint(hitPoint);
        Vec3f outward = hitPoint - sphere.center;
        const float outwardLength = length(outward);
        outward = outwardLength > 0.0f ? outward / outwardLength : Vec3f{0.0f, 0.0f, 1.0f};
        si.position = sphere.center + outward * sphere.radius;
        // outward is unit within a few roundings (difference, length, division), and any unit
        // vector times the radius lies on the sphere: then a product and a sum.
        si.positionError = (abs(sphere.center) + abs(outward * sphere.radius)) * gamma(8);
        si.geometricNormal = outward;
        si.shadingNormal = outward;
        if (sphere.needsUv) si.uv = sphereUv(outward);
        si.material = sphere.material;
        if (toWorld) placeInWorld(*toWorld, si);
    }
    return si;
}

// canonicalizeHit (unless `kHitIsCanonical`), then makeSurfaceInteraction, for a hit that is not on
// a still mesh: the shape's placement computed once for both. Out of line: scenes without moving
// shapes, spheres or instances never call it.
template <bool kHitIsCanonical>
[[gnu::noinline]] inline SurfaceInteraction resolveOtherHit(const SceneGeometry& scene, const Ray& ray,
                                                            Hit& hit, const FaceFrames* faceFrames) {
    const ShapeRef shape = scene.shapeOf(hit);
    const std::optional<Transform> toWorld = placementOf(scene, shape, ray.time);
    if constexpr (!kHitIsCanonical) canonicalizeShapeHit(scene, shape, toWorld, ray, hit);
    return shapeInteraction(scene, shape, toWorld, ray, hit, faceFrames);
}

}  // namespace detail

// `faceFrames`, when given, supplies the normals of instanced triangles.
inline SurfaceInteraction makeSurfaceInteraction(const SceneGeometry& scene, const Ray& ray, const Hit& hit,
                                                 const FaceFrames* faceFrames = nullptr) {
    const ShapeRef shape = scene.shapeOf(hit);
    return detail::shapeInteraction(scene, shape, detail::placementOf(scene, shape, ray.time), ray, hit,
                                    faceFrames);
}

// canonicalizeHit (unless `kHitIsCanonical`: the backend's hits already are) and then
// makeSurfaceInteraction, with a still mesh's vertices loaded once for both and its triangle's
// normal and shading frame taken from `faceFrames` when given (the same bits as computing them).
template <bool kHitIsCanonical>
[[gnu::always_inline]] inline SurfaceInteraction resolveHit(const SceneGeometry& scene, const Ray& ray,
                                                            Hit& hit,
                                                            const FaceFrames* faceFrames = nullptr) {
    // One named result on every path, so that it is built in the caller's place (NRVO), not
    // copied on return (bench/README.md, "Speed tricks").
    SurfaceInteraction si;
    const ShapeRef shape = scene.shapeOf(hit);
    if (shape.kind == ShapeKind::Mesh && !scene.meshes[shape.index].moves()) [[likely]] {
        const TriangleMesh& mesh = scene.meshes[shape.index];
        const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
        // The vertices are read where they are used and the shape written field by field: kept in
        // locals, they went through the stack in pieces the loads could not be forwarded from
        // (bench/README.md, "Speed tricks").
        const Vec3f* positions = mesh.positions.data();
        if constexpr (!kHitIsCanonical)
            detail::recomputeTriangleHit(ray.origin, ray.direction, positions[index[0]], positions[index[1]],
                                         positions[index[2]], ray, hit);
        si.shape.kind = ShapeKind::Mesh;
        si.shape.index = shape.index;
        si.shape.primitive = shape.primitive;
        const Frame* faceFrame = faceFrames ? faceFrames->find(shape.index, shape.primitive) : nullptr;
        if (!detail::triangleInteraction(mesh, index, positions[index[0]], positions[index[1]],
                                         positions[index[2]], hit, si, faceFrame)) [[unlikely]]
            si.geometricNormal = si.shadingNormal = normalize(-ray.direction);
        return si;
    }
    si = detail::resolveOtherHit<kHitIsCanonical>(scene, ray, hit, faceFrames);
    return si;
}

}  // namespace penumbra
