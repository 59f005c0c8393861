// A ray leaving a triangle from its hit point, offset by the point's error bound
// (core/ray_offset.h), never hits that triangle again, at any distance from the origin and any
// size: tilted triangles, triangles in a coordinate plane far from the origin (whose zero
// coordinate once got a fixed offset far below the rounding of the others), grazing directions,
// unnormalized directions (shadow rays), towards either side.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/ray_offset.h"
#include "geometry/surface_interaction.h"
#include "geometry/triangle.h"

namespace penumbra {
namespace {

TEST(SelfIntersection, ARayLeavingATriangleNeverHitsItAgain) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
    int rays = 0;
    for (float scale : {1e-6f, 1e-3f, 1.0f, 1e3f, 1e5f, 1e7f}) {
        for (float distance : {0.0f, 1.0f, 1e3f}) {  // of the triangle from the origin, in its sizes
            for (int trial = 0; trial < 200; ++trial) {
                const bool inPlane = trial % 2 == 0;  // y = 0 exactly, like a floor
                const Vec3f centre =
                    Vec3f{unit(rng), inPlane ? 0.0f : unit(rng), unit(rng)} * (distance * scale);
                Vec3f p[3];
                for (Vec3f& v : p)
                    v = centre + Vec3f{unit(rng), inPlane ? 0.0f : unit(rng), unit(rng)} * scale;
                if (inPlane)
                    for (Vec3f& v : p) v.y = 0.0f;
                SceneGeometry scene;
                TriangleMesh mesh;
                mesh.positions = {p[0], p[1], p[2]};
                mesh.indices = {0, 1, 2};
                scene.meshes.push_back(mesh);
                const Vec3f n = triangleNormal(p[0], p[1], p[2]);
                if (n == Vec3f{0.0f, 0.0f, 0.0f}) continue;
                Hit hit;
                hit.u = positive(rng);
                hit.v = (1.0f - hit.u) * positive(rng);
                const SurfaceInteraction si = makeSurfaceInteraction(scene, Ray{}, hit);
                const float vertices[9] = {p[0].x, p[0].y, p[0].z, p[1].x, p[1].y,
                                           p[1].z, p[2].x, p[2].y, p[2].z};
                for (float side : {1.0f, -1.0f}) {
                    const Vec3f normal = si.geometricNormal * side;
                    const Frame frame = Frame::fromNormal(normal);
                    const Vec3f origin = offsetRayOrigin(si.position, si.positionError, normal);
                    for (int k = 0; k < 20; ++k) {
                        // Cosines down to 1e-6: grazing rays are the ones rounding lets back in.
                        const float cosine = std::pow(10.0f, -6.0f * positive(rng));
                        const float sine = std::sqrt(1.0f - cosine * cosine),
                                    phi = 6.2831853f * positive(rng);
                        Vec3f direction = frame.toWorld({sine * std::cos(phi), sine * std::sin(phi), cosine});
                        if (k % 2 == 1) direction = direction * (scale * std::pow(10.0f, 3.0f * unit(rng)));
                        TriangleHit th;
                        ASSERT_FALSE(intersectTriangleWatertight(WatertightRay(origin, direction), vertices,
                                                                 0.0f, std::numeric_limits<float>::infinity(),
                                                                 th))
                            << "scale " << scale << " distance " << distance << " trial " << trial << " t "
                            << th.t;
                        ++rays;
                    }
                }
            }
        }
    }
    EXPECT_GT(rays, 100000);
}

}  // namespace
}  // namespace penumbra
