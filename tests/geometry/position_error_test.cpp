// The error bounds of computed hit points (SurfaceInteraction::positionError), checked against the
// same points computed in long double: a sphere's reprojected hit, and hits on moving triangles and
// spheres, whose bounds grow through the motion transform (detail::placeInWorld). Then what the
// bounds are for: a ray leaving such a point from offsetRayOrigin (core/ray_offset.h) never hits
// the surface it leaves again, tested the way the backends test it (a moving shape in object space,
// the ray taken there by the inverse of its transform, as the BVH's instances do).
//
// Spheres and triangles from 1e-6 to 1e7 in size, at 0 to 1000 of their sizes from the origin,
// with transforms that rotate, scale (also unevenly) and translate far.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/ray_offset.h"
#include "geometry/sphere.h"
#include "geometry/surface_interaction.h"
#include "geometry/triangle.h"

namespace penumbra {
namespace {

using Real = long double;

struct Vec3L {
    Real x, y, z;
    Real operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
};

Vec3L widen(Vec3f v) { return {v.x, v.y, v.z}; }

// The float matrix of `t` applied to p without rounding (long double holds each product and sum
// of these floats to far below float's precision): the surface a moving shape has at that time.
Vec3L applyExactly(const Transform& t, const Vec3L& p) {
    const auto& m = t.matrix().m;
    Vec3L r{};
    Real* out[3] = {&r.x, &r.y, &r.z};
    for (int row = 0; row < 3; ++row)
        *out[row] = Real(m[row][0]) * p.x + Real(m[row][1]) * p.y + Real(m[row][2]) * p.z + Real(m[row][3]);
    return r;
}

// The inverse of `t`'s float matrix, in long double.
Vec3L applyInverseExactly(const Transform& t, const Vec3L& p) {
    const auto& m = t.matrix().m;
    Real a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = m[i][j];
    const Real q[3] = {p.x - m[0][3], p.y - m[1][3], p.z - m[2][3]};
    const Real det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    // Cramer's rule: column j replaced by q.
    auto solve = [&](int j) {
        Real b[3][3];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) b[i][k] = k == j ? q[i] : a[i][k];
        return (b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0])) /
               det;
    };
    return {solve(0), solve(1), solve(2)};
}

// Whether the box `p` +- `error` holds a point of the sphere (centre c, radius r): the box's
// nearest and farthest points from the centre straddle the radius.
bool boxMeetsSphere(Vec3f p, Vec3f error, const Vec3L& c, Real r) {
    Real nearest = 0, farthest = 0;
    for (int i = 0; i < 3; ++i) {
        const Real d = std::fabs(c[i] - Real(p[i]));
        const Real gap = std::max(Real(0), d - Real(error[i]));
        nearest += gap * gap;
        farthest += (d + Real(error[i])) * (d + Real(error[i]));
    }
    return nearest <= r * r && r * r <= farthest;
}

// Whether `p` lies within `error` of `truth` in every coordinate.
bool withinBound(Vec3f p, Vec3f error, const Vec3L& truth) {
    for (int i = 0; i < 3; ++i)
        if (std::fabs(Real(p[i]) - truth[i]) > Real(error[i])) return false;
    return true;
}

// A random motion over the shutter: two keys, each a rotation about a random axis, a scale
// (uneven on odd trials) and a translation of up to `reach`.
MotionTransform randomMotion(std::mt19937& rng, float reach, bool uneven) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), scale(0.25f, 4.0f);
    MotionTransform motion;
    for (int k = 0; k < 2; ++k) {
        TransformKey key;
        const float s = scale(rng);
        key.scale = uneven ? Vec3f{scale(rng), scale(rng), scale(rng)} : Vec3f{s, s, s};
        key.rotation =
            Quaternion::fromAxisAngle({unit(rng), unit(rng), unit(rng) + 2.0f}, 180.0f * unit(rng));
        key.translation = Vec3f{unit(rng), unit(rng), unit(rng)} * reach;
        motion.keys.push_back(key);
    }
    return motion;
}

// A direction in the hemisphere of `normal`, down to grazing (cosine 1e-6); every other one
// unnormalized, as shadow rays are.
Vec3f leavingDirection(std::mt19937& rng, Vec3f normal, float scale, int k) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
    const float cosine = std::pow(10.0f, -6.0f * positive(rng));
    const float sine = std::sqrt(1.0f - cosine * cosine), phi = 6.2831853f * positive(rng);
    const Vec3f direction =
        Frame::fromNormal(normal).toWorld({sine * std::cos(phi), sine * std::sin(phi), cosine});
    return k % 2 == 1 ? direction * (scale * std::pow(10.0f, 3.0f * unit(rng))) : direction;
}

constexpr float kScales[] = {1e-6f, 1e-3f, 1.0f, 1e3f, 1e5f, 1e7f};
constexpr float kDistances[] = {0.0f, 1.0f, 1e3f};  // of the shape from the origin, in its sizes

// A ray from outside aimed at a random point of the sphere's disk as seen from there, so that it
// hits; the hit as a backend reports it (t from intersectSphere, as canonicalizeHit computes it).
bool shootAtSphere(std::mt19937& rng, const SceneGeometry& scene, const Sphere& sphere, Ray& ray, Hit& hit) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const Vec3f away = normalize(Vec3f{unit(rng), unit(rng), unit(rng)});
    ray.origin = sphere.center + away * (sphere.radius * (1.5f + 10.0f * std::fabs(unit(rng))));
    const Vec3f aim = sphere.center + Vec3f{unit(rng), unit(rng), unit(rng)} * (0.5f * sphere.radius);
    ray.direction = aim - ray.origin;
    hit = scene.idsOf({ShapeKind::Sphere, 0, 0});
    return intersectSphere(ray.origin, ray.direction, sphere.center, sphere.radius, 0.0f, ray.tfar, hit.t);
}

// Whether a ray from `origin` leaves the sphere's surface without meeting it again. Leaving along
// the outward normal, the origin must lie outside the exact sphere and the ray must miss it; along
// the inward normal, the origin must lie inside the exact sphere, so that what the ray hits is the
// exit (for grazing rays, whose chord is shorter than the discriminant's rounding, about
// sqrt(2^-24) radii, the exit's t is only that accurate; it is still the exit).
::testing::AssertionResult leavesSphere(Vec3f origin, Vec3f direction, Vec3f center, float radius,
                                        bool outward) {
    const Vec3L f{Real(origin.x) - center.x, Real(origin.y) - center.y, Real(origin.z) - center.z};
    const Real c = f.x * f.x + f.y * f.y + f.z * f.z - Real(radius) * Real(radius);
    if (outward ? !(c > 0) : !(c < 0))
        return ::testing::AssertionFailure() << "the origin is not " << (outward ? "outside" : "inside")
                                             << " the sphere: |o - c|^2 - r^2 = " << double(c);
    float t = 0.0f;
    const bool hits =
        intersectSphere(origin, direction, center, radius, 0.0f, std::numeric_limits<float>::infinity(), t);
    if (outward && hits)
        return ::testing::AssertionFailure() << "an outward ray hits the sphere again at t " << t;
    if (!outward && !(hits && t > 0.0f))
        return ::testing::AssertionFailure() << "an inward ray finds no exit";
    return ::testing::AssertionSuccess();
}

// The hit point and its bound computed in SSE lanes (detail::setBarycentricPoint) are Vec3f's
// p0 b0 + p1 b1 + p2 b2 and (|p0 b0| + |p1 b1| + |p2 b2|) gamma(7) bit for bit: vertices of mixed
// signs and scales, barycentrics from 0 to 1 with b0 = 1 - b1 - b2 as the hit computes it.
TEST(PositionError, TheLanesHitPointIsTheVectorFormulaBitForBit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f), unit(0.0f, 1.0f);
    const auto same = [](Vec3f a, Vec3f b) { return std::memcmp(&a, &b, sizeof(Vec3f)) == 0; };
    for (int i = 0; i < 100000; ++i) {
        const float scale = std::exp2(float(i % 60) - 30.0f);
        const Vec3f p0{coordinate(rng) * scale, coordinate(rng), coordinate(rng) * 1000.0f};
        const Vec3f p1{coordinate(rng) * scale, coordinate(rng), coordinate(rng) * 1000.0f};
        const Vec3f p2{coordinate(rng) * scale, coordinate(rng), coordinate(rng) * 1000.0f};
        const float b1 = unit(rng), b2 = unit(rng) * (1.0f - b1), b0 = 1.0f - b1 - b2;
        SurfaceInteraction si;
        detail::setBarycentricPoint(p0, p1, p2, b0, b1, b2, si);
        ASSERT_TRUE(same(si.position, p0 * b0 + p1 * b1 + p2 * b2)) << i;
        ASSERT_TRUE(same(si.positionError, (abs(p0 * b0) + abs(p1 * b1) + abs(p2 * b2)) * gamma(7))) << i;
    }
}

TEST(PositionError, SphereHitsLieWithinTheirBound) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    int checked = 0;
    for (float scale : kScales)
        for (float distance : kDistances)
            for (int trial = 0; trial < 2000; ++trial) {
                SceneGeometry scene;
                Sphere sphere;
                sphere.center = Vec3f{unit(rng), unit(rng), unit(rng)} * (distance * scale);
                sphere.radius = scale * (0.1f + std::fabs(unit(rng)));
                scene.spheres.push_back(sphere);
                Ray ray;
                Hit hit;
                if (!shootAtSphere(rng, scene, sphere, ray, hit)) continue;
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                ASSERT_TRUE(
                    boxMeetsSphere(si.position, si.positionError, widen(sphere.center), sphere.radius))
                    << "scale " << scale << " distance " << distance << " trial " << trial;
                ++checked;
            }
    EXPECT_GT(checked, 30000);
}

TEST(PositionError, MovingTriangleHitsLieWithinTheirBound) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
    int checked = 0;
    for (float scale : kScales)
        for (float distance : kDistances)
            for (int trial = 0; trial < 1000; ++trial) {
                SceneGeometry scene;
                TriangleMesh mesh;
                const Vec3f centre = Vec3f{unit(rng), unit(rng), unit(rng)} * (distance * scale);
                for (int v = 0; v < 3; ++v)
                    mesh.positions.push_back(centre + Vec3f{unit(rng), unit(rng), unit(rng)} * scale);
                mesh.indices = {0, 1, 2};
                mesh.motion = randomMotion(rng, distance * scale, trial % 2 == 1);
                scene.meshes.push_back(mesh);
                Ray ray;
                ray.time = positive(rng);
                Hit hit = scene.idsOf({ShapeKind::Mesh, 0, 0});
                hit.u = positive(rng);
                hit.v = (1.0f - hit.u) * positive(rng);
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                const Real b1 = hit.u, b2 = hit.v, b0 = 1 - b1 - b2;
                const Vec3L p0 = widen(mesh.positions[0]), p1 = widen(mesh.positions[1]),
                            p2 = widen(mesh.positions[2]);
                const Vec3L object{b0 * p0.x + b1 * p1.x + b2 * p2.x, b0 * p0.y + b1 * p1.y + b2 * p2.y,
                                   b0 * p0.z + b1 * p1.z + b2 * p2.z};
                const Vec3L truth = applyExactly(mesh.motion.at(ray.time), object);
                ASSERT_TRUE(withinBound(si.position, si.positionError, truth))
                    << "scale " << scale << " distance " << distance << " trial " << trial;
                ++checked;
            }
    EXPECT_EQ(checked, 18000);
}

TEST(PositionError, MovingSphereHitsLieWithinTheirBound) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
    int checked = 0;
    for (float scale : kScales)
        for (float distance : kDistances)
            for (int trial = 0; trial < 1000; ++trial) {
                SceneGeometry scene;
                Sphere sphere;
                sphere.center = Vec3f{unit(rng), unit(rng), unit(rng)} * (distance * scale);
                sphere.radius = scale * (0.1f + std::fabs(unit(rng)));
                sphere.motion = randomMotion(rng, distance * scale, trial % 2 == 1);
                scene.spheres.push_back(sphere);
                // Shoot in object space, then take the ray to the world, so that it hits.
                Ray objectRay;
                Hit hit;
                if (!shootAtSphere(rng, scene, sphere, objectRay, hit)) continue;
                Ray ray;
                ray.time = positive(rng);
                const Transform toWorld = sphere.motion.at(ray.time);
                ray.origin = toWorld.applyPoint(objectRay.origin);
                ray.direction = toWorld.applyVector(objectRay.direction);
                canonicalizeHit(scene, ray, hit);
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                // The point of the (exact, transformed) sphere nearest along the radius through
                // the computed point: the bound must reach it.
                const Vec3L object = applyInverseExactly(toWorld, widen(si.position));
                const Vec3L c = widen(sphere.center);
                const Vec3L radial{object.x - c.x, object.y - c.y, object.z - c.z};
                const Real length =
                    std::sqrt(radial.x * radial.x + radial.y * radial.y + radial.z * radial.z);
                const Real k = Real(sphere.radius) / length;
                const Vec3L onSphere{c.x + radial.x * k, c.y + radial.y * k, c.z + radial.z * k};
                ASSERT_TRUE(withinBound(si.position, si.positionError, applyExactly(toWorld, onSphere)))
                    << "scale " << scale << " distance " << distance << " trial " << trial;
                ++checked;
            }
    EXPECT_GT(checked, 15000);
}

TEST(PositionError, RaysLeavingASphereNeverMeetItAgain) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    int rays = 0;
    for (float scale : kScales)
        for (float distance : kDistances)
            for (int trial = 0; trial < 2000; ++trial) {
                SceneGeometry scene;
                Sphere sphere;
                sphere.center = Vec3f{unit(rng), unit(rng), unit(rng)} * (distance * scale);
                sphere.radius = scale * (0.1f + std::fabs(unit(rng)));
                scene.spheres.push_back(sphere);
                Ray ray;
                Hit hit;
                if (!shootAtSphere(rng, scene, sphere, ray, hit)) continue;
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                for (bool outward : {true, false}) {
                    const Vec3f normal = outward ? si.geometricNormal : -si.geometricNormal;
                    const Vec3f origin = offsetRayOrigin(si.position, si.positionError, normal);
                    for (int k = 0; k < 20; ++k) {
                        ASSERT_TRUE(leavesSphere(origin, leavingDirection(rng, normal, scale, k),
                                                 sphere.center, sphere.radius, outward))
                            << "scale " << scale << " distance " << distance << " trial " << trial;
                        ++rays;
                    }
                }
            }
    EXPECT_GT(rays, 100000);
}

TEST(PositionError, RaysLeavingAMovingTriangleNeverHitItAgain) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
    int rays = 0;
    for (float scale : kScales)
        for (float distance : kDistances)
            for (int trial = 0; trial < 2000; ++trial) {
                SceneGeometry scene;
                TriangleMesh mesh;
                const Vec3f centre = Vec3f{unit(rng), unit(rng), unit(rng)} * (distance * scale);
                for (int v = 0; v < 3; ++v)
                    mesh.positions.push_back(centre + Vec3f{unit(rng), unit(rng), unit(rng)} * scale);
                mesh.indices = {0, 1, 2};
                mesh.motion = randomMotion(rng, distance * scale, trial % 2 == 1);
                scene.meshes.push_back(mesh);
                if (triangleNormal(mesh.positions[0], mesh.positions[1], mesh.positions[2]) == Vec3f{})
                    continue;
                Ray ray;
                ray.time = positive(rng);
                Hit hit = scene.idsOf({ShapeKind::Mesh, 0, 0});
                hit.u = positive(rng);
                hit.v = (1.0f - hit.u) * positive(rng);
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                const Transform toObject = mesh.motion.at(ray.time).inverse();
                const Vec3f* p = mesh.positions.data();
                const float vertices[9] = {p[0].x, p[0].y, p[0].z, p[1].x, p[1].y,
                                           p[1].z, p[2].x, p[2].y, p[2].z};
                for (float side : {1.0f, -1.0f}) {
                    const Vec3f normal = si.geometricNormal * side;
                    const Vec3f origin = offsetRayOrigin(si.position, si.positionError, normal);
                    for (int k = 0; k < 20; ++k) {
                        const Vec3f direction = leavingDirection(rng, normal, scale, k);
                        TriangleHit th;
                        ASSERT_FALSE(intersectTriangleWatertight(
                            WatertightRay(toObject.applyPoint(origin), toObject.applyVector(direction)),
                            vertices, 0.0f, std::numeric_limits<float>::infinity(), th))
                            << "scale " << scale << " distance " << distance << " trial " << trial << " t "
                            << th.t;
                        ++rays;
                    }
                }
            }
    EXPECT_GT(rays, 100000);
}

TEST(PositionError, RaysLeavingAMovingSphereNeverMeetItAgain) {
    std::mt19937 rng(19);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
    int rays = 0;
    for (float scale : kScales)
        for (float distance : kDistances)
            for (int trial = 0; trial < 2000; ++trial) {
                SceneGeometry scene;
                Sphere sphere;
                sphere.center = Vec3f{unit(rng), unit(rng), unit(rng)} * (distance * scale);
                sphere.radius = scale * (0.1f + std::fabs(unit(rng)));
                sphere.motion = randomMotion(rng, distance * scale, trial % 2 == 1);
                scene.spheres.push_back(sphere);
                Ray objectRay;
                Hit hit;
                if (!shootAtSphere(rng, scene, sphere, objectRay, hit)) continue;
                Ray ray;
                ray.time = positive(rng);
                const Transform toWorld = sphere.motion.at(ray.time), toObject = toWorld.inverse();
                ray.origin = toWorld.applyPoint(objectRay.origin);
                ray.direction = toWorld.applyVector(objectRay.direction);
                canonicalizeHit(scene, ray, hit);
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                for (bool outward : {true, false}) {
                    const Vec3f normal = outward ? si.geometricNormal : -si.geometricNormal;
                    const Vec3f origin = offsetRayOrigin(si.position, si.positionError, normal);
                    for (int k = 0; k < 20; ++k) {
                        const Vec3f direction = leavingDirection(rng, normal, scale, k);
                        ASSERT_TRUE(leavesSphere(toObject.applyPoint(origin), toObject.applyVector(direction),
                                                 sphere.center, sphere.radius, outward))
                            << "scale " << scale << " distance " << distance << " trial " << trial;
                        ++rays;
                    }
                }
            }
    EXPECT_GT(rays, 90000);
}

}  // namespace
}  // namespace penumbra
