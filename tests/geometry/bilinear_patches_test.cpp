// Bilinear patches (geometry/bilinear_patches.h) in both backends: a saddle z = x y, which one patch
// is exactly, against the ray/paraboloid quadratic solved in double; hits on curved patches lying
// on the patch's parametric surface; a flat parallelogram patch hit as its two triangles are; the
// shading point's normal, uv and error bound against closed forms; rays leaving a patch never
// meeting it again at once; the two backends' hits the same bits, single rays and packets; the
// crosscheck on curved patches; and the loader's bilinear meshes and errors.
#include "geometry/bilinear_patches.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <optional>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "core/hash.h"
#include "core/ray_offset.h"
#include "core/sampling.h"
#include "geometry/surface_derivatives.h"
#include "geometry/surface_interaction.h"
#include "geometry/triangle.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"
#include "tools/crosscheck.h"

namespace penumbra {
namespace {

using testing::catchInputError;

float uniform(uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(0xb11, index, dimension) >> 32));
}

// z = x y over [-1, 1]^2: p(u, v) = (2u - 1, 2v - 1, (1 - 2u)(1 - 2v)).
constexpr std::array<Vec3f, 4> kSaddle = {Vec3f{-1, -1, 1}, Vec3f{1, -1, -1}, Vec3f{-1, 1, -1},
                                          Vec3f{1, 1, 1}};

// The nearest t > 0 where o + t d meets z = x y with |x|, |y| <= 1, in double; also how far that
// point is from the square's edge (in x, y) and the smallest gap between the quadratic's roots
// relative to t (small when the ray grazes the surface).
struct SaddleHit {
    double t, x, y, edgeDistance, rootGap;
};
std::optional<SaddleHit> saddleHit(Vec3f o, Vec3f d) {
    const double a = double(d.x) * d.y, b = double(o.x) * d.y + double(o.y) * d.x - d.z,
                 c = double(o.x) * o.y - o.z;
    std::array<double, 2> roots;
    int count = 0;
    if (std::abs(a) < 1e-300) {
        if (b == 0.0) return std::nullopt;
        roots[count++] = -c / b;
    } else {
        const double discriminant = b * b - 4.0 * a * c;
        if (discriminant < 0.0) return std::nullopt;
        const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
        roots[count++] = q / a;
        roots[count++] = c / q;
        if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
    }
    for (int k = 0; k < count; ++k) {
        const double t = roots[k];
        if (!(t > 1e-6)) continue;
        const double x = o.x + t * d.x, y = o.y + t * d.y;
        const double edge = std::min(1.0 - std::abs(x), 1.0 - std::abs(y));
        // A root just outside the square is not a hit, but one that close is not tested.
        if (edge < -1e-4) continue;
        const double gap = count == 2 ? std::abs(roots[1] - roots[0]) / std::max(t, 1e-30) : 1.0;
        return SaddleHit{t, x, y, edge, gap};
    }
    return std::nullopt;
}

TEST(BilinearPatchesTest, ASaddleIsHitWhereTheRayMeetsZEqualsXY) {
    int hits = 0, misses = 0, compared = 0;
    for (int i = 0; i < 40000; ++i) {
        const Vec3f origin{6.0f * uniform(i, 0) - 3.0f, 6.0f * uniform(i, 1) - 3.0f,
                           6.0f * uniform(i, 2) - 3.0f};
        const Vec3f target{2.6f * uniform(i, 3) - 1.3f, 2.6f * uniform(i, 4) - 1.3f,
                           2.0f * uniform(i, 5) - 1.0f};
        const Vec3f direction = normalize(target - origin);
        const std::optional<SaddleHit> expected = saddleHit(origin, direction);
        // Rays within 1e-4 of the edge, or grazing (roots closer than 1e-3 t), are left out: there
        // float's rounding decides.
        if (expected && (expected->edgeDistance < 1e-4 || expected->rootGap < 1e-3)) continue;
        ++compared;
        BilinearPatchHit hit;
        const bool found = intersectBilinearPatch(kSaddle.data(), origin, direction, 0.0f, 1e30f, hit);
        ASSERT_EQ(found, expected.has_value()) << i;
        if (!found) {
            ++misses;
            continue;
        }
        ++hits;
        EXPECT_NEAR(hit.t, expected->t, 2e-5 * (1.0 + expected->t)) << i;
        EXPECT_NEAR(hit.u, (expected->x + 1.0) / 2.0, 2e-5) << i;
        EXPECT_NEAR(hit.v, (expected->y + 1.0) / 2.0, 2e-5) << i;
    }
    EXPECT_GT(compared, 35000);
    EXPECT_GT(hits, 10000);
    EXPECT_GT(misses, 10000);
}

// Random curved patches: a ray aimed at p(u0, v0) (not grazing it) meets the patch no farther than
// that point, and
// where it does, the point at the hit's (u, v) is the ray's point at t.
TEST(BilinearPatchesTest, HitsOnCurvedPatchesLieOnTheirParametricSurface) {
    for (int i = 0; i < 20000; ++i) {
        std::array<Vec3f, 4> p;
        for (int k = 0; k < 4; ++k)
            p[k] = Vec3f{float(k & 1), float(k >> 1), 0.0f} * 2.0f +
                   Vec3f{uniform(i, 3 * k), uniform(i, 3 * k + 1), 2.0f * uniform(i, 3 * k + 2)} -
                   Vec3f{0.5f, 0.5f, 0.5f};
        const float u0 = 0.02f + 0.96f * uniform(i, 20), v0 = 0.02f + 0.96f * uniform(i, 21);
        const Vec3f target = bilinear::point(p.data(), u0, v0);
        const Vec3f origin =
            Vec3f{1.0f, 1.0f, 1.0f} + sampleUniformSphere({uniform(i, 22), uniform(i, 23)}) * 6.0f;
        const Vec3f direction = normalize(target - origin);
        const float t0 = length(target - origin);
        // A ray grazing the surface there (|cos| < 1e-3) touches it or misses by rounding.
        const Vec3f normal = cross(bilinear::dpdu(p.data(), v0), bilinear::dpdv(p.data(), u0));
        if (std::abs(dot(normalize(normal), direction)) < 1e-3f) continue;
        BilinearPatchHit hit;
        ASSERT_TRUE(intersectBilinearPatch(p.data(), origin, direction, 0.0f, 1e30f, hit)) << i;
        EXPECT_LE(hit.t, t0 * (1.0f + 1e-4f)) << i;
        const Vec3f onPatch = bilinear::point(p.data(), hit.u, hit.v);
        EXPECT_LT(length(onPatch - (origin + direction * hit.t)), 2e-4f * (1.0f + hit.t)) << i;
        // The range is respected: nothing beyond a tMax short of the hit.
        BilinearPatchHit none;
        EXPECT_FALSE(intersectBilinearPatch(p.data(), origin, direction, 0.0f, hit.t * 0.999f, none) &&
                     none.t > hit.t * 0.999f)
            << i;
    }
}

TEST(BilinearPatchesTest, AFlatParallelogramIsHitAsItsTwoTriangles) {
    const std::array<Vec3f, 4> p = {Vec3f{0, 0, 0}, Vec3f{2, 0.5f, 0}, Vec3f{0.3f, 1.5f, 0.2f},
                                    Vec3f{2.3f, 2.0f, 0.2f}};
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3f origin{4.0f * uniform(i, 0) - 1.0f, 4.0f * uniform(i, 1) - 1.0f, 3.0f};
        const Vec3f direction = normalize(Vec3f{0.3f * uniform(i, 2), 0.3f * uniform(i, 3), -1.0f});
        BilinearPatchHit hit;
        const bool found = intersectBilinearPatch(p.data(), origin, direction, 0.0f, 1e30f, hit);
        // The triangles (p00, p10, p11) and (p00, p11, p01).
        std::optional<float> triangleT;
        for (const auto& [a, b, c] : {std::array{0, 1, 3}, std::array{0, 3, 2}}) {
            const float vertices[9] = {p[a].x, p[a].y, p[a].z, p[b].x, p[b].y,
                                       p[b].z, p[c].x, p[c].y, p[c].z};
            TriangleHit th;
            if (intersectTriangleWatertight(WatertightRay(origin, direction), vertices, 0.0f, 1e30f, th))
                triangleT = th.t;
        }
        if (found != triangleT.has_value()) {
            // Only at the outline, where the two tests round differently.
            const Vec3f q = origin + direction * (found ? hit.t : *triangleT);
            const float edge = found ? std::min({hit.u, 1.0f - hit.u, hit.v, 1.0f - hit.v}) : 0.0f;
            EXPECT_LT(edge, 1e-5f) << i << " at " << q.x << ", " << q.y;
            continue;
        }
        if (!found) continue;
        ++hits;
        EXPECT_NEAR(hit.t, *triangleT, 1e-5f) << i;
    }
    EXPECT_GT(hits, 3000);
}

SceneGeometry saddleScene(bool reversed, bool withNormals, bool withUvs) {
    SceneGeometry scene;
    BilinearPatches patches;
    patches.positions.assign(kSaddle.begin(), kSaddle.end());
    patches.indices = {0, 1, 2, 3};
    patches.reversed = reversed;
    // Normals all +z (the saddle's at its centre), and uvs (u, v) scaled by 3 and 5.
    if (withNormals) patches.normals.assign(4, Vec3f{0, 0, 1});
    if (withUvs) patches.uvs = {{0, 0}, {3, 0}, {0, 5}, {3, 5}};
    scene.patches.push_back(patches);
    return scene;
}

// The saddle's normal at (x, y) is (-y, -x, 1) normalized (cross(dp/du, dp/dv) points up); reversed
// turns it down, vertex normals turn it to their side; the point is within its error bound of the
// surface; uvs are interpolated, and the surface derivatives are those of the uvs' parameters.
TEST(BilinearPatchesTest, TheShadingPointMatchesTheSaddlesClosedForms) {
    for (const bool reversed : {false, true})
        for (const bool withNormals : {false, true}) {
            const SceneGeometry scene = saddleScene(reversed, withNormals, true);
            const BvhAccelerator bvh(scene);
            for (int i = 0; i < 2000; ++i) {
                const float x = 1.9f * uniform(i, 0) - 0.95f, y = 1.9f * uniform(i, 1) - 0.95f;
                Ray ray;
                ray.origin = {x, y, 5.0f};
                ray.direction = {0.0f, 0.0f, -1.0f};
                Hit hit;
                ASSERT_TRUE(bvh.intersect(ray, hit));
                const SurfaceInteraction si = makeSurfaceInteraction(scene, ray, hit);
                const double z = double(x) * y;
                EXPECT_NEAR(ray.at(hit.t).z, z, 1e-5);
                // The surface's point at the hit's (u, v), in double, within the error bound.
                const double px = 2.0 * hit.u - 1.0, py = 2.0 * hit.v - 1.0;
                EXPECT_LE(std::abs(si.position.x - px), si.positionError.x) << i;
                EXPECT_LE(std::abs(si.position.y - py), si.positionError.y) << i;
                EXPECT_LE(std::abs(si.position.z - px * py), si.positionError.z) << i;
                Vec3f expected = normalize(Vec3f{-y, -x, 1.0f});
                if (reversed && !withNormals) expected = -expected;
                EXPECT_NEAR(si.geometricNormal.x, expected.x, 1e-4f) << i;
                EXPECT_NEAR(si.geometricNormal.y, expected.y, 1e-4f) << i;
                EXPECT_NEAR(si.geometricNormal.z, expected.z, 1e-4f) << i;
                if (withNormals) {
                    EXPECT_NEAR(si.shadingNormal.z, 1.0f, 1e-6f);
                }
                EXPECT_NEAR(si.uv.x, 3.0f * (x + 1.0f) / 2.0f, 1e-4f);
                EXPECT_NEAR(si.uv.y, 5.0f * (y + 1.0f) / 2.0f, 1e-4f);
                // dp/ds = dp/du / 3 = (2, 0, 2 y) / 3; dp/dt = dp/dv / 5 = (0, 2, 2 x) / 5.
                const SurfaceDerivatives d = surfaceDerivatives(scene, si, 0.0f);
                EXPECT_NEAR(d.dpdu.x, 2.0f / 3.0f, 1e-4f);
                EXPECT_NEAR(d.dpdu.z, 2.0f * y / 3.0f, 1e-4f);
                EXPECT_NEAR(d.dpdv.y, 2.0f / 5.0f, 1e-4f);
                EXPECT_NEAR(d.dpdv.z, 2.0f * x / 5.0f, 1e-4f);
            }
        }
}

// Rays leaving a curved patch from a shading point (the origin offset by its error bound) in every
// direction: none meets its patch again within twice the offset (both backends).
TEST(BilinearPatchesTest, ARayLeavingAPatchDoesNotMeetItAgainAtOnce) {
    SceneGeometry scene;
    BilinearPatches patches;
    // A strongly twisted patch far from the origin, where rounding is coarse.
    for (const Vec3f& p : kSaddle) patches.positions.push_back(p * 3.0f + Vec3f{1000.0f, -700.0f, 300.0f});
    patches.indices = {0, 1, 2, 3};
    scene.patches.push_back(patches);
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    int tooNear = 0, rays = 0;
    for (int i = 0; i < 40000; ++i) {
        Ray toward;
        toward.origin =
            Vec3f{1000.0f, -700.0f, 300.0f} + sampleUniformSphere({uniform(i, 0), uniform(i, 1)}) * 10.0f;
        const Vec3f target =
            bilinear::point(scene.patches[0].cornerPositions(0).data(), uniform(i, 2), uniform(i, 3));
        toward.direction = normalize(target - toward.origin);
        Hit hit;
        if (!bvh.intersect(toward, hit)) continue;
        const SurfaceInteraction si = makeSurfaceInteraction(scene, toward, hit);
        const Vec3f out = sampleUniformSphere({uniform(i, 4), uniform(i, 5)});
        const Vec3f side = dot(out, si.geometricNormal) >= 0.0f ? si.geometricNormal : -si.geometricNormal;
        Ray leaving;
        leaving.origin = offsetRayOrigin(si.position, si.positionError, side);
        leaving.direction = out;
        const float offset = length(leaving.origin - si.position);
        ++rays;
        for (int backend = 0; backend < 2; ++backend) {
            Hit again;
            const bool found =
                backend == 0 ? bvh.intersect(leaving, again) : embree.intersect(leaving, again);
            if (found && again.t <= 2.0f * offset) ++tooNear;
        }
    }
    EXPECT_GT(rays, 20000);
    EXPECT_EQ(tooNear, 0);
}

// Curved patches: the twisted band and the torus of scenes/bilinear-patches.json, smaller.
Scene curvedPatchScene() {
    Scene scene;
    BilinearPatches band;
    const int segments = 24;
    for (int i = 0; i <= segments; ++i) {
        const float a = 2.0f * kPi * float(i) / float(segments), twist = a / 2.0f;
        const Vec3f centre{1.2f * std::cos(a), 0.0f, 1.2f * std::sin(a)};
        const Vec3f across{std::cos(twist) * std::cos(a), std::sin(twist), std::cos(twist) * std::sin(a)};
        band.positions.push_back(centre - across * 0.4f);
        band.positions.push_back(centre + across * 0.4f);
    }
    for (uint32_t i = 0; i < uint32_t(segments); ++i)
        band.indices.insert(band.indices.end(), {2 * i, 2 * i + 2, 2 * i + 1, 2 * i + 3});
    scene.patches.push_back(band);
    BilinearPatches saddles;
    for (int k = 0; k < 3; ++k)
        for (const Vec3f& p : kSaddle)
            saddles.positions.push_back(p * 0.5f + Vec3f{float(k) - 1.0f, 0.3f, 0.0f});
    saddles.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    scene.patches.push_back(saddles);
    TriangleMesh floor;
    floor.positions = {{-3, -1, -3}, {3, -1, -3}, {3, -1, 3}, {-3, -1, 3}};
    floor.indices = {0, 2, 1, 0, 3, 2};
    scene.meshes.push_back(floor);
    scene.camera.lookFrom = {0, 2, 4};
    scene.camera.lookAt = {0, 0, 0};
    scene.film.width = 64;
    scene.film.height = 48;
    return scene;
}

TEST(BilinearPatchesTest, BothBackendsFindTheSameHitsBitForBit) {
    const Scene scene = curvedPatchScene();
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    int patchHits = 0;
    std::array<Ray, EmbreeAccelerator::kPacketSize> packet;
    for (int i = 0; i < 40000; ++i) {
        Ray ray;
        ray.origin = sampleUniformSphere({uniform(i, 0), uniform(i, 1)}) * 4.0f;
        ray.direction = normalize(Vec3f{uniform(i, 2), uniform(i, 3), uniform(i, 4)} * 2.0f - Vec3f{1, 1, 1} -
                                  ray.origin * 0.2f);
        Hit a, b;
        const bool foundA = bvh.intersect(ray, a), foundB = embree.intersect(ray, b);
        ASSERT_EQ(foundA, foundB) << i;
        EXPECT_EQ(bvh.occluded(ray), foundA) << i;
        EXPECT_EQ(embree.occluded(ray), foundA) << i;
        if (!foundA || scene.shapeOf(a).kind != ShapeKind::BilinearPatches) continue;
        ++patchHits;
        EXPECT_EQ(a.geomId, b.geomId) << i;
        EXPECT_EQ(a.primId, b.primId) << i;
        EXPECT_EQ(a.t, b.t) << i;
        EXPECT_EQ(a.u, b.u) << i;
        EXPECT_EQ(a.v, b.v) << i;
        EXPECT_EQ(a.geometricNormal, b.geometricNormal) << i;
        // Embree's packets ask the same test.
        packet[i % packet.size()] = ray;
        if (i % packet.size() == packet.size() - 1) {
            std::array<Hit, EmbreeAccelerator::kPacketSize> hits;
            bool found[EmbreeAccelerator::kPacketSize];
            embree.intersectPacket(packet.data(), int(packet.size()), hits.data(), found);
            for (size_t k = 0; k < packet.size(); ++k) {
                Hit single;
                ASSERT_EQ(found[k], bvh.intersect(packet[k], single));
                if (found[k]) {
                    EXPECT_EQ(hits[k].t, single.t);
                }
            }
        }
    }
    EXPECT_GT(patchHits, 1500);
}

TEST(BilinearPatchesTest, TheCrosscheckFindsNoUnexplainedDisagreement) {
    const Scene scene = curvedPatchScene();
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    CrosscheckOptions options;
    options.rays = 40'000;
    options.measureThroughput = false;
    const std::vector<CrosscheckRay> rays = generateCrosscheckRays(scene, embree, options);
    const CrosscheckReport report = compareBackends(scene, bvh, embree, rays, options);
    EXPECT_EQ(report.unexplained(), 0u);
    EXPECT_EQ(report.selfIntersections(), 0u);
    EXPECT_GT(report.samePrimitiveHits, 10000u);
}

std::string patchScene(const std::string& shape) {
    return R"({"materials": {"m": {"type": "lambert"}}, "shapes": [)" + shape + "]}";
}

TEST(BilinearPatchesTest, TheLoaderReadsBilinearMeshesAndNamesWhatIsWrong) {
    const Scene scene = parseScene(patchScene(R"({"type": "bilinear_mesh", "material": "m",
        "positions": [[0, 0, 0], [1, 0, 1], [0, 1, 1], [1, 1, 0]], "indices": [0, 1, 2, 3],
        "normals": [[0, 0, 2], [0, 0, 1], [0, 0, 1], [0, 0, 1]], "uvs": [[0, 0], [1, 0], [0, 1], [1, 1]],
        "transform": [{"scale": [-2, 1, 1]}]})"),
                                   "scene.json");
    ASSERT_EQ(scene.patches.size(), 1u);
    const BilinearPatches& patches = scene.patches[0];
    EXPECT_EQ(patches.patchCount(), 1u);
    EXPECT_EQ(patches.positions[1], (Vec3f{-2, 0, 1}));
    EXPECT_NEAR(patches.normals[0].z, 1.0f, 1e-6f);
    // The mirror turns cross(dp/du, dp/dv) over: the front stays where it was.
    EXPECT_TRUE(patches.reversed);

    InputError e = catchInputError([] {
        parseScene(patchScene(R"({"type": "bilinear_mesh", "material": "m",
            "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, 2]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/indices");
    EXPECT_CONTAINS(e.what(), "4 per patch");
    e = catchInputError([] {
        parseScene(patchScene(R"({"type": "bilinear_mesh", "material": "m",
            "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], "indices": [0, 1, 2, 4]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/indices/3");
    e = catchInputError([] {
        parseScene(patchScene(R"({"type": "bilinear_mesh", "material": "m", "emission": {"radiance": 1},
            "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], "indices": [0, 1, 2, 3]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "emission");
    e = catchInputError([] {
        parseScene(patchScene(R"({"type": "bilinear_mesh", "material": "m", "normals": [[0, 0, 1]],
            "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], "indices": [0, 1, 2, 3]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "4 normals");
}

}  // namespace
}  // namespace penumbra
