// Curves (geometry/curves.h) in both backends: a straight curve's width at each parameter, a bent
// one's hits against the distance to its centre line computed densely in double, B-splines and
// linear widths against their bases, a ribbon's width turning with its normal, no hit within twice
// the radius of the origin, the crosscheck on a groom explaining every disagreement (and leaving a
// hit in a curve's middle unexplained), the loader's curves and errors, and a white furnace of
// hair fibers (materials/hair_bsdf.h) shading curves.
#include "geometry/curves.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "core/hash.h"
#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/render_scene.h"
#include "tools/crosscheck.h"

namespace penumbra {
namespace {

using testing::catchInputError;

float uniform(uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(0xc0e, index, dimension) >> 32));
}

// One curve of `points` (Bezier) with widths w0 to w1, in a set of its own.
Curves curveOf(std::vector<Vec3f> points, float w0, float w1, CurveType type = CurveType::Flat,
               std::vector<Vec3f> normals = {}) {
    Curves curves;
    curves.type = type;
    appendCurve(curves, points, linearCurveRadii(points.size(), CurveBasis::Bezier, w0, w1),
                CurveBasis::Bezier, normals, 0);
    return curves;
}

// The x axis from 0 to 1, its parameter u = x (evenly spaced control points), 0.2 wide at its start
// and 0.05 at its end: its radius at x is 0.1 - 0.075 x.
Curves straightCurve() {
    return curveOf({{0, 0, 0}, {1.0f / 3, 0, 0}, {2.0f / 3, 0, 0}, {1, 0, 0}}, 0.2f, 0.05f);
}

TEST(CurvesTest, AStraightCurveIsAsWideAsItsRadiusAtEachParameter) {
    SceneGeometry scene;
    scene.curves.push_back(straightCurve());
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    for (int i = 1; i < 20; ++i) {
        const float x = float(i) / 20.0f, radius = 0.1f - 0.075f * x;
        for (const float f : {0.0f, 0.5f, -0.5f, 0.97f, -0.97f, 1.03f, -1.03f, 1.5f}) {
            Ray ray;
            ray.origin = {x, f * radius, 5.0f};
            ray.direction = {0.0f, 0.0f, -1.0f};
            CurveHit ours;
            const bool found =
                intersectCurveSegment(scene.curves[0], 0, ray.origin, ray.direction, 0.0f, ray.tfar, ours);
            ASSERT_EQ(found, std::abs(f) < 1.0f) << x << " " << f;
            Hit bvhHit, embreeHit;
            EXPECT_EQ(bvh.intersect(ray, bvhHit), found) << x << " " << f;
            EXPECT_EQ(embree.intersect(ray, embreeHit), found) << x << " " << f;
            if (!found) continue;
            EXPECT_NEAR(ours.t, 5.0f, 1e-5f);
            EXPECT_NEAR(ours.u, x, 1e-4f);
            EXPECT_NEAR(std::abs(ours.v), std::abs(f), 2e-3f) << x << " " << f;
            EXPECT_EQ(bvhHit.t, ours.t);
            EXPECT_NEAR(embreeHit.t, 5.0f, 1e-5f);
            EXPECT_NEAR(embreeHit.u, x, 1e-3f);
            // (Embree's v is its quads' own coordinate across, not distance over radius: on a
            // tapered curve the two differ by several hundredths; hits are recomputed with ours.)
            // The two sides of the curve have opposite signs of v.
            if (f != 0.0f) {
                CurveHit mirrored;
                ASSERT_TRUE(intersectCurveSegment(scene.curves[0], 0, {x, -f * radius, 5.0f}, ray.direction,
                                                  0.0f, ray.tfar, mirrored));
                EXPECT_LT(ours.v * mirrored.v, 0.0f);
            }
        }
    }
}

// The hit a ray should find on a Bezier segment, in double, by the definition: at each local
// minimum of the distance between the ray and the centre line (sampled at 2^16 + 1 parameters),
// the ray meets the curve if that distance is within the radius there and the point is more than
// twice the radius ahead of the origin; the nearest such. `ambiguous`: some local minimum is
// within 2% of the radius of the edge, or at the curve's ends (its flat end caps).
struct TrueHit {
    bool hit = false, ambiguous = false;
    double ratio = 0.0, t = 1e30, u = 0.0;
};
TrueHit trueHit(const Curves& curves, Vec3f origin, Vec3f direction) {
    const Vec3f* c = curves.controlPoints(0);
    const float* r = curves.controlRadii(0);
    const double dd = double(dot(direction, direction));
    constexpr int kSamples = 65536;
    std::vector<double> distance(kSamples + 1), along(kSamples + 1), radius(kSamples + 1);
    for (int i = 0; i <= kSamples; ++i) {
        const double u = double(i) / kSamples, s = 1.0 - u;
        const double b[4] = {s * s * s, 3 * s * s * u, 3 * s * u * u, u * u * u};
        double p[3] = {0, 0, 0};
        radius[i] = 0;
        for (int k = 0; k < 4; ++k) {
            for (int a = 0; a < 3; ++a) p[a] += b[k] * double(c[k][a]);
            radius[i] += b[k] * double(r[k]);
        }
        const double rel[3] = {p[0] - origin.x, p[1] - origin.y, p[2] - origin.z};
        along[i] = (rel[0] * direction.x + rel[1] * direction.y + rel[2] * direction.z) / dd;
        double perp2 = 0;
        for (int a = 0; a < 3; ++a) perp2 += std::pow(rel[a] - along[i] * double(direction[a]), 2);
        distance[i] = std::sqrt(perp2);
    }
    TrueHit truth;
    for (int i = 0; i <= kSamples; ++i) {
        const bool minimum =
            (i == 0 || distance[i] <= distance[i - 1]) && (i == kSamples || distance[i] <= distance[i + 1]);
        if (!minimum || !(along[i] * std::sqrt(dd) > 2.0 * radius[i])) continue;
        const double ratio = distance[i] / radius[i];
        if (std::abs(ratio - 1.0) < 0.02 ||
            (ratio < 1.0 && (i < kSamples / 100 || i > kSamples - kSamples / 100)))
            truth.ambiguous = true;
        if (ratio < 1.0 && along[i] < truth.t)
            truth = {true, truth.ambiguous, ratio, along[i], double(i) / kSamples};
    }
    return truth;
}

TEST(CurvesTest, ABentCurveIsHitWhereTheRayPassesWithinItsRadius) {
    // A tapered, bent segment (a hair's), rays aimed at random points near it from random directions.
    const Curves curves =
        curveOf({{0, 0, 0}, {0.3f, 0.5f, 0.1f}, {-0.2f, 0.9f, 0.4f}, {0.1f, 1.2f, 0.2f}}, 0.08f, 0.01f);
    int hits = 0, decided = 0;
    for (uint64_t i = 0; i < 3000; ++i) {
        const float u = uniform(i, 0);
        const Vec3f onCurve = curve::bezier(curves.controlPoints(0), u);
        const float radius = curve::bezier(curves.controlRadii(0), u);
        const Vec3f offset =
            Vec3f{uniform(i, 1) - 0.5f, uniform(i, 2) - 0.5f, uniform(i, 3) - 0.5f} * (4.0f * radius);
        const Vec3f direction =
            normalize(Vec3f{uniform(i, 4) - 0.5f, uniform(i, 5) - 0.5f, uniform(i, 6) - 0.5f});
        const Vec3f origin = onCurve + offset - direction * 3.0f;
        const TrueHit truth = trueHit(curves, origin, direction);
        // Within 2% of the edge either answer is right (the test's pieces are straight within a
        // twentieth of the narrowest width, refined on the curve); so it is at the curve's ends.
        if (truth.ambiguous) continue;
        ++decided;
        CurveHit ours;
        const bool found = intersectCurveSegment(curves, 0, origin, direction, 0.0f, 1e30f, ours);
        ASSERT_EQ(found, truth.hit) << i << " ratio " << truth.ratio;
        if (!found) continue;
        ++hits;
        // Two Newton steps leave the nearest point within a few hundredths of the radius.
        EXPECT_NEAR(ours.t, truth.t, 0.003) << i;
        EXPECT_NEAR(ours.u, truth.u, 0.003) << i;
        EXPECT_NEAR(std::abs(ours.v), truth.ratio, 0.03) << i;
    }
    EXPECT_GT(decided, 2500);
    EXPECT_GT(hits, 800);
}

// Our BVH boxes a long segment in dyadic pieces, each tested by the whole segment's halving followed
// down to it: the nearest of the pieces' hits is the whole test's, bit for bit, at every level.
TEST(CurvesTest, APiecesHitsAreTheWholeSegmentsBitForBit) {
    const Curves curves =
        curveOf({{0, 0, 0}, {0.3f, 0.5f, 0.1f}, {-0.2f, 0.9f, 0.4f}, {0.1f, 1.2f, 0.2f}}, 0.08f, 0.01f);
    int hits = 0;
    for (uint64_t i = 0; i < 3000; ++i) {
        const float u = uniform(i, 0), radius = curve::bezier(curves.controlRadii(0), u);
        const Vec3f direction =
            normalize(Vec3f{uniform(i, 4) - 0.5f, uniform(i, 5) - 0.5f, uniform(i, 6) - 0.5f});
        const Vec3f origin =
            curve::bezier(curves.controlPoints(0), u) +
            Vec3f{uniform(i, 1) - 0.5f, uniform(i, 2) - 0.5f, uniform(i, 3) - 0.5f} * (3.0f * radius) -
            direction * 3.0f;
        CurveHit whole;
        const bool found = intersectCurveSegment(curves, 0, origin, direction, 0.0f, 1e30f, whole);
        hits += found;
        for (uint32_t level = 1; level <= 3; ++level) {
            bool any = false;
            CurveHit nearest;
            for (uint32_t index = 0; index < (1u << level); ++index) {
                CurveHit piece;
                if (intersectCurveSegment(curves, 0, origin, direction, 0.0f, 1e30f, piece, {level, index}) &&
                    (!any || piece.t < nearest.t))
                    nearest = piece, any = true;
            }
            ASSERT_EQ(any, found) << i << " level " << level;
            if (!found) continue;
            EXPECT_EQ(nearest.t, whole.t) << i;
            EXPECT_EQ(nearest.u, whole.u) << i;
            EXPECT_EQ(nearest.v, whole.v) << i;
        }
    }
    EXPECT_GT(hits, 1000);
}

TEST(CurvesTest, BSplinesAndLinearWidthsMatchTheirBases) {
    const std::vector<Vec3f> points{{0, 0, 0}, {1, 2, 0}, {2, -1, 1}, {3, 0, 2}, {4, 3, 0}, {5, 1, -1}};
    Curves curves;
    const std::vector<float> radii = linearCurveRadii(points.size(), CurveBasis::BSpline, 0.4f, 0.1f);
    appendCurve(curves, points, radii, CurveBasis::BSpline, {}, 0);
    ASSERT_EQ(curves.segmentCount(), 3u);
    for (size_t segment = 0; segment < 3; ++segment)
        for (int i = 0; i <= 10; ++i) {
            const double t = i / 10.0, s = 1.0 - t;
            // The uniform cubic B-spline basis on points segment .. segment + 3.
            const double b[4] = {s * s * s / 6, (3 * t * t * t - 6 * t * t + 4) / 6,
                                 (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6, t * t * t / 6};
            double expected[3] = {0, 0, 0};
            for (int k = 0; k < 4; ++k)
                for (int a = 0; a < 3; ++a) expected[a] += b[k] * double(points[segment + k][a]);
            const Vec3f got = curve::bezier(curves.controlPoints(segment), float(t));
            for (int a = 0; a < 3; ++a) EXPECT_NEAR(got[a], expected[a], 2e-5) << segment << " " << t;
            // The width is linear in u along the whole curve: 0.4 at its start, 0.1 at its end.
            const double u = (double(segment) + t) / 3.0;
            EXPECT_NEAR(2.0f * curve::bezier(curves.controlRadii(segment), float(t)), 0.4 - 0.3 * u, 1e-6);
            const Vec2f range = curves.uRanges[segment];
            EXPECT_NEAR(range.x + (range.y - range.x) * t, u, 1e-6);
        }
    // A Bezier curve of 7 points is two segments; 5 or 3 points make none.
    EXPECT_EQ(curveSegmentCount(7, CurveBasis::Bezier), 2u);
    EXPECT_EQ(curveSegmentCount(5, CurveBasis::Bezier), 0u);
    EXPECT_EQ(curveSegmentCount(3, CurveBasis::BSpline), 0u);
    const std::vector<float> bezierRadii = linearCurveRadii(7, CurveBasis::Bezier, 1.0f, 0.0f);
    for (int j = 0; j < 7; ++j) EXPECT_NEAR(bezierRadii[j], 0.5f * (1.0f - float(j) / 6.0f), 1e-7f);
}

TEST(CurvesTest, ARibbonIsAsWideAsItsWidthTimesTheCosineOfItsNormalWithTheRay) {
    // Along x, its normal +z: seen from above it is 0.2 wide; from 60 degrees off its normal, across
    // the curve, half that.
    SceneGeometry scene;
    scene.curves.push_back(curveOf({{0, 0, 0}, {1.0f / 3, 0, 0}, {2.0f / 3, 0, 0}, {1, 0, 0}}, 0.2f, 0.2f,
                                   CurveType::Ribbon, {{0, 0, 1}, {0, 0, 1}}));
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    const float angle = 60.0f * float(M_PI) / 180.0f;
    for (const auto& [direction, width] :
         {std::pair{Vec3f{0, 0, -1}, 0.2f}, std::pair{Vec3f{0, std::sin(angle), -std::cos(angle)}, 0.1f}}) {
        // d: the ray's distance from the axis, perpendicular to both.
        for (const float f : {0.0f, 0.9f, -0.9f, 1.1f, -1.1f}) {
            const Vec3f across = normalize(cross({1, 0, 0}, direction));
            Ray ray;
            ray.origin = Vec3f{0.5f, 0, 0} + across * (f * 0.5f * width) - direction * 4.0f;
            ray.direction = direction;
            const bool expected = std::abs(f) < 1.0f;
            Hit hit;
            EXPECT_EQ(bvh.intersect(ray, hit), expected) << width << " " << f;
            EXPECT_EQ(embree.intersect(ray, hit), expected) << width << " " << f;
            EXPECT_EQ(embree.occluded(ray), expected) << width << " " << f;
        }
    }
}

TEST(CurvesTest, NoCurveIsSeenWithinTwiceItsRadiusOfTheOrigin) {
    SceneGeometry scene;
    scene.curves.push_back(curveOf({{-1, 0, 0}, {-1.0f / 3, 0, 0}, {1.0f / 3, 0, 0}, {1, 0, 0}}, 0.2f, 0.2f));
    const BvhAccelerator bvh(scene);
    const EmbreeAccelerator embree(scene);
    for (const float k : {1.0f, 1.9f, 2.1f, 3.0f}) {  // in radii
        Ray ray;
        ray.origin = {0.1f, k * 0.1f, 0.0f};
        ray.direction = {0.0f, -1.0f, 0.0f};
        Hit hit;
        EXPECT_EQ(bvh.intersect(ray, hit), k > 2.0f) << k;
        EXPECT_EQ(embree.intersect(ray, hit), k > 2.0f) << k;
    }
}

// 400 hairs rising from a disk, bent, tapered: a groom in miniature over a floor.
Scene groomScene(CurveType type) {
    Scene scene;
    scene.materials.push_back(Material(Lambert{Rgb(0.5f)}));
    Curves curves;
    curves.type = type;
    std::vector<Vec3f> normals;
    for (uint64_t i = 0; i < 400; ++i) {
        const float a = 6.2831853f * uniform(i, 10), r = 0.8f * std::sqrt(uniform(i, 11));
        const float x = r * std::cos(a), z = r * std::sin(a), bend = 0.6f * (uniform(i, 12) - 0.5f);
        const std::vector<Vec3f> points{{x, 0, z},
                                        {x + 0.2f * bend, 0.33f, z},
                                        {x + 0.6f * bend, 0.66f, z + 0.2f * bend},
                                        {x + bend, 1.0f, z + 0.4f * bend}};
        if (type == CurveType::Ribbon) normals = {{0, 0, 1}, normalize(Vec3f{1, 0, 1})};
        appendCurve(curves, points, linearCurveRadii(4, CurveBasis::Bezier, 0.02f, 0.004f),
                    CurveBasis::Bezier, normals, i % 2);
    }
    scene.curves.push_back(curves);
    TriangleMesh floor;
    floor.positions = {{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}};
    floor.indices = {0, 2, 1, 0, 3, 2};
    scene.meshes.push_back(floor);
    scene.camera.lookFrom = {0, 0.5f, 3};
    scene.camera.lookAt = {0, 0.5f, 0};
    scene.film.width = 64;
    scene.film.height = 48;
    return scene;
}

TEST(CurvesTest, TheCrosscheckExplainsEveryDisagreementOnAGroom) {
    for (const CurveType type : {CurveType::Flat, CurveType::Ribbon}) {
        const Scene scene = groomScene(type);
        const BvhAccelerator bvh(scene);
        const EmbreeAccelerator embree(scene);
        CrosscheckOptions options;
        options.rays = 40'000;
        options.measureThroughput = false;
        const std::vector<CrosscheckRay> rays = generateCrosscheckRays(scene, embree, options);
        const CrosscheckReport report = compareBackends(scene, bvh, embree, rays, options);
        EXPECT_EQ(report.unexplained(), 0u) << int(type);
        for (size_t k = 0; k < std::min<size_t>(report.mismatches.size(), 3); ++k) {
            const Mismatch& m = report.mismatches[k];
            if (m.kind != MismatchKind::Unexplained) continue;
            ADD_FAILURE() << "ray " << crosscheckRayKindName(m.ray.kind) << " " << m.ray.index << ": bvh "
                          << m.ours.hitSomething << " prim " << m.ours.hit.primId << " t " << m.ours.hit.t
                          << " u " << m.ours.hit.u << " v " << m.ours.hit.v << "; embree "
                          << m.embree.hitSomething << " prim " << m.embree.hit.primId << " t "
                          << m.embree.hit.t << " u " << m.embree.hit.u << " v " << m.embree.hit.v;
        }
        EXPECT_EQ(report.selfIntersections(), 0u) << int(type);
        EXPECT_GT(double(report.agreements) / double(report.rayCount), 0.99) << int(type);
        EXPECT_GT(report.samePrimitiveHits, 4000u) << int(type);
    }
}

TEST(CurvesTest, TheClassifierLeavesAHitInACurvesMiddleUnexplained) {
    Scene scene;
    scene.curves.push_back(straightCurve());
    const MismatchClassifier classifier(scene);
    auto classify = [&](float x, float f) {
        CrosscheckRay cray;
        cray.ray.origin = {x, f * (0.1f - 0.075f * x), 5.0f};
        cray.ray.direction = {0.0f, 0.0f, -1.0f};
        BackendAnswer ours, embree;
        ours.hitSomething = ours.hasHit = true;
        ours.hit.t = 5.0f;
        ours.hit.u = x;
        ours.hit.v = f;
        ours.hit.geomId = scene.curvesGeomId(0);
        return classifier.classify(cray, ours, embree);
    };
    EXPECT_EQ(classify(0.5f, 0.0f), MismatchKind::Unexplained);
    EXPECT_EQ(classify(0.5f, 0.5f), MismatchKind::Unexplained);
    EXPECT_EQ(classify(0.5f, 0.995f), MismatchKind::CurveApproximation);
}

TEST(CurvesTest, BothBackendsRenderAGroomAlike) {
    Scene scene = groomScene(CurveType::Cylinder);
    scene.film.samplesPerPixel = 4;
    // Hair fibers (the fiber frame and offset of both backends' hits) under a uniform sky.
    HairBsdf fur;
    fur.sigmaA = HairBsdf::sigmaAFromConcentration(0.3f, 0.5f);
    scene.materials.push_back(Material(fur));
    scene.curves[0].material = uint32_t(scene.materials.size() - 1);
    scene.environment = EnvironmentLight::constant(Rgb(1.0f));
    const Film a = testing::renderScene(scene, 2, AcceleratorKind::Embree);
    const Film b = testing::renderScene(scene, 2, AcceleratorKind::Bvh);
    int differing = 0;
    double sumA = 0.0, sumB = 0.0;
    for (int y = 0; y < scene.film.height; ++y)
        for (int x = 0; x < scene.film.width; ++x) {
            const Rgb pa = a.at(x, y).mean(), pb = b.at(x, y).mean();
            differing += !(pa == pb);
            sumA += pa.luminance();
            sumB += pb.luminance();
        }
    EXPECT_GT(sumA, 0.0);
    // A pixel differs when one of its rays met a curve approximation disagreement (about 0.2% of
    // rays in `penumbra crosscheck`); most pixels are bit for bit the same (measured: 21 of 3,072
    // differ, the sums 1959.894 and 1959.868).
    EXPECT_LT(differing, scene.film.width * scene.film.height / 10);
    EXPECT_NEAR(sumA, sumB, 0.01 * sumA);
}

std::string curvesScene(const std::string& shape,
                        const std::string& materials = R"({"m": {"type": "lambert"}})") {
    return R"({"materials": )" + materials + R"(, "shapes": [)" + shape + "]}";
}

TEST(CurvesTest, TheLoaderReadsCurvesAndNamesWhatIsWrong) {
    const Scene scene = parseScene(curvesScene(R"({"type": "curves", "material": "m", "basis": "bspline",
        "curve_type": "cylinder", "points": [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0], [1, 0, 0], [1, 1, 0], [1, 2, 0], [1, 3, 0], [1, 4, 0]],
        "curve_sizes": [4, 5], "curve_widths": [[0.1, 0.1], [0.2, 0.0]], "transform": [{"scale": 2}]})"),
                                   "scene.json");
    ASSERT_EQ(scene.curves.size(), 1u);
    const Curves& curves = scene.curves[0];
    EXPECT_EQ(curves.type, CurveType::Cylinder);
    EXPECT_EQ(curves.segmentCount(), 3u);  // 1 + 2 B-spline segments
    // The first curve's start: the B-spline's (0, 0 + 4 + 2, 0) / 6 scaled by 2, its width 0.1 x 2.
    const Vec3f start = curves.controlPoints(0)[0];
    EXPECT_NEAR(start.y, 2.0f, 1e-5f);
    EXPECT_NEAR(curves.controlRadii(0)[0], 0.1f, 1e-6f);
    EXPECT_NEAR(curves.controlRadii(2)[3], 0.0f, 1e-6f);

    InputError e = catchInputError([] {
        parseScene(
            curvesScene(
                R"({"type": "curves", "material": "m", "width": 0.1, "points": [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0], [0, 4, 0]]})"),
            "scene.json");
    });
    EXPECT_CONTAINS(e.what(),
                    "/shapes/0: curve 0 (counting from 0) has 5 points: a Bezier curve needs 3 n + 1");
    e = catchInputError([] {
        parseScene(
            curvesScene(
                R"({"type": "curves", "material": "m", "points": [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]]})"),
            "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "either \"width\"");
    e = catchInputError([] {
        parseScene(curvesScene(R"({"type": "curves", "material": "m", "width": 1, "curve_type": "ribbon",
            "points": [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]], "normals": [[1, 0, 0]]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "a ribbon needs a normal at each segment boundary");
    e = catchInputError([] {
        parseScene(curvesScene(R"({"type": "curves", "material": "m", "width": 1, "curve_sizes": [3],
            "points": [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/curve_sizes/0");
    e = catchInputError([] {
        parseScene(curvesScene(R"({"type": "curves", "material": "m", "width": 1, "emission": {"radiance": 1},
            "points": [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]]})"),
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "emission");
}

// A white furnace: hair fibers that absorb nothing (sigma_a 0) under a uniform sky of radiance 1,
// with no floor, send back exactly the light they receive, whatever the fiber's frame and offset
// h: every pixel's expectation is 1. Every path ends in the sky (max depth high enough that the
// paths cut short weigh below the tolerance).
TEST(CurvesTest, HairFibersThatAbsorbNothingAreWhiteInAFurnace) {
    std::string points, sizes;
    for (int i = 0; i < 60; ++i) {
        const float x = -0.6f + 0.02f * float(i);
        points += fmt::format("{}[{}, -0.5, 0], [{}, -0.1, 0.05], [{}, 0.2, -0.05], [{}, 0.5, 0]",
                              i ? ", " : "", x, x + 0.01f, x - 0.01f, x);
        sizes += std::string(i ? ", " : "") + "4";
    }
    for (const char* type : {"flat", "cylinder"}) {
        Scene scene = parseScene(
            R"({"camera": {"look_from": [0, 0, 3], "look_at": [0, 0, 0], "fov": 30},
                "film": {"resolution": [24, 24], "spp": 64}, "integrator": {"max_depth": 64, "roulette_start": 64},
                "environment": {"type": "constant", "radiance": 1},
                "materials": {"hair": {"type": "hair", "sigma_a": 0, "beta_m": 0.3, "beta_n": 0.3}},
                "shapes": [{"type": "curves", "material": "hair", "curve_type": ")" +
                std::string(type) + R"(", "width": 0.015, "curve_sizes": [)" + sizes + R"(], "points": [)" +
                points + "]}]}",
            "furnace.json");
        const Film film = testing::renderScene(scene, 2, AcceleratorKind::Embree);
        double sum = 0.0, sumSquares = 0.0;
        const int n = scene.film.width * scene.film.height;
        for (int y = 0; y < scene.film.height; ++y)
            for (int x = 0; x < scene.film.width; ++x) {
                const double v = film.at(x, y).mean().g;
                sum += v;
                sumSquares += v * v;
            }
        const double mean = sum / n, spread = std::sqrt(std::max(0.0, sumSquares / n - mean * mean));
        EXPECT_NEAR(mean, 1.0, 5.0 * spread / std::sqrt(double(n)) + 1e-3) << type;
        EXPECT_LT(spread, 0.5) << type;
    }
}

}  // namespace
}  // namespace penumbra
