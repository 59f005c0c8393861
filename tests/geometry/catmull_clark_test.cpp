// Catmull-Clark subdivision (geometry/catmull_clark.h) against what the scheme guarantees: on a
// mesh of valence-4 quads the limit surface is the uniform bicubic B-spline of the control points,
// so limit points and normals have closed forms (the (1, 4, 1) / 6 tensor mask and its
// derivatives); limit positions do not move when the mesh is refined further (the limit masks are
// the refinement's fixed points, so a wrong weight anywhere shows, at any valence); normals face
// the winding's side and agree with the finely refined surface; planes stay flat; polygons of any
// size; uvs interpolated linearly; and the errors.
#include "geometry/catmull_clark.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"

namespace penumbra {
namespace {

// A torus of `segments` x `sides` quads around +y, counter-clockwise seen from outside: every
// vertex of valence 4, so its limit surface is a periodic uniform bicubic B-spline.
PolygonMesh torus(int segments, int sides) {
    PolygonMesh mesh;
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            const double a = 2.0 * M_PI * i / segments, b = 2.0 * M_PI * j / sides;
            const double r = 2.0 + 0.7 * std::cos(b);
            mesh.positions.push_back(
                {float(r * std::cos(a)), float(0.7 * std::sin(b)), float(r * std::sin(a))});
        }
    auto id = [&](int i, int j) {
        return uint32_t(((i + segments) % segments) * sides + (j + sides) % sides);
    };
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            mesh.faceSizes.push_back(4);
            mesh.corners.insert(mesh.corners.end(), {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
        }
    return mesh;
}

// A cube of six quads about the origin (valence 3 at every corner), facing out.
PolygonMesh cube() {
    PolygonMesh mesh;
    for (int i = 0; i < 8; ++i)
        mesh.positions.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
    mesh.faceSizes.assign(6, 4);
    mesh.corners = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
    return mesh;
}

// The angle between two unit vectors, precise near 0 (acos of a float dot product is not: 1 ulp
// below 1 is 3.5e-4 rad).
float angleBetween(Vec3f a, Vec3f b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// The vertex of `mesh` nearest to p, and its distance.
size_t nearest(const TriangleMesh& mesh, Vec3f p, float* distance = nullptr) {
    size_t best = 0;
    float bestDistance = std::numeric_limits<float>::infinity();
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        if (const float d = length(mesh.positions[i] - p); d < bestDistance) bestDistance = d, best = i;
    if (distance) *distance = bestDistance;
    return best;
}

TEST(CatmullClark, RegularQuadsReachTheBicubicBSplineAndItsNormal) {
    const int segments = 8, sides = 6;
    const PolygonMesh control = torus(segments, sides);
    const TriangleMesh surface = catmullClarkSubdivide(control, 2);
    auto p = [&](int i, int j) {
        return control.positions[((i + segments) % segments) * sides + (j + sides) % sides];
    };
    const float w[3] = {1.0f / 6.0f, 4.0f / 6.0f, 1.0f / 6.0f};
    float worstPosition = 0.0f, worstAngle = 0.0f;
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            // The B-spline at the knot of control point (i, j), and its two derivatives.
            Vec3f point{0, 0, 0}, du{0, 0, 0}, dv{0, 0, 0};
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b) point = point + p(i + a, j + b) * (w[a + 1] * w[b + 1]);
            for (int b = -1; b <= 1; ++b) du = du + (p(i + 1, j + b) - p(i - 1, j + b)) * (0.5f * w[b + 1]);
            for (int a = -1; a <= 1; ++a) dv = dv + (p(i + a, j + 1) - p(i + a, j - 1)) * (0.5f * w[a + 1]);
            float distance;
            const size_t v = nearest(surface, point, &distance);
            worstPosition = std::max(worstPosition, distance);
            // Corners run (i, j) -> (i, j + 1) -> (i + 1, j + 1): the front is dv x du.
            const Vec3f n = normalize(cross(dv, du));
            worstAngle = std::max(worstAngle, angleBetween(n, surface.normals[v]));
        }
    std::printf("largest distance from the B-spline's knot points %.2e, largest normal angle %.2e rad\n",
                worstPosition, worstAngle);
    // Float rounding of the refinement at coordinates of about 3: a few 1e-7.
    EXPECT_LT(worstPosition, 2e-6f);
    EXPECT_LT(worstAngle, 1e-5f);
}

// Every vertex of level L is a vertex of level L + 1, and its limit point is the same: the limit
// mask is the fixed point of the refinement rules, at valence 3 (the cube's corners) and 4.
TEST(CatmullClark, LimitPointsAreTheSameAtEveryLevel) {
    for (const PolygonMesh& control : {cube(), torus(5, 3)}) {
        const TriangleMesh coarse = catmullClarkSubdivide(control, 1);
        const TriangleMesh fine = catmullClarkSubdivide(control, 3);
        float worst = 0.0f, worstAngle = 0.0f;
        for (size_t i = 0; i < coarse.positions.size(); ++i) {
            float distance;
            const size_t j = nearest(fine, coarse.positions[i], &distance);
            worst = std::max(worst, distance);
            worstAngle = std::max(worstAngle, angleBetween(coarse.normals[i], fine.normals[j]));
        }
        std::printf("%zu control faces: limit points move by at most %.2e, normals by %.2e rad\n",
                    control.faceSizes.size(), worst, worstAngle);
        EXPECT_LT(worst, 1e-6f);
        EXPECT_LT(worstAngle, 1e-5f);
    }
}

TEST(CatmullClark, TheCubeBecomesARoundedBoxFacingOut) {
    const TriangleMesh surface = catmullClarkSubdivide(cube(), 3);
    EXPECT_EQ(surface.triangleCount(), 6u * 64u * 2u);
    for (size_t t = 0; t < surface.triangleCount(); ++t) {
        const Vec3f a = surface.positions[surface.indices[3 * t]],
                    b = surface.positions[surface.indices[3 * t + 1]],
                    c = surface.positions[surface.indices[3 * t + 2]];
        EXPECT_GT(dot(cross(b - a, c - a), a + b + c), 0.0f) << t;  // wound outward
    }
    for (size_t i = 0; i < surface.positions.size(); ++i) {
        EXPECT_GT(dot(surface.normals[i], surface.positions[i]), 0.0f) << i;
        // Inside the control cube (the surface is a convex combination of its points).
        EXPECT_LT(maxComponent(abs(surface.positions[i])), 1.0f);
    }
    // The limit point of a valence-3 vertex of quads, (9 s + 4 sum e + sum d) / 24, on the control
    // cube itself: for the corner (1, 1, 1), e sums to (1, 1, 1) and d to -(1, 1, 1), so 1/2 (1, 1, 1).
    float distance;
    nearest(surface, Vec3f{0.5f, 0.5f, 0.5f}, &distance);
    EXPECT_LT(distance, 1e-6f);
}

TEST(CatmullClark, PlanesStayFlatAndBoundariesFollowTheirBSpline) {
    PolygonMesh grid;
    const int n = 3;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            grid.positions.push_back({float(x), float(y), 0.0f});
            grid.uvs.push_back({float(x) / n, float(y) / n});
        }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = uint32_t(y * (n + 1) + x);
            grid.faceSizes.push_back(4);
            grid.corners.insert(grid.corners.end(), {a, a + 1, a + uint32_t(n) + 2, a + uint32_t(n) + 1});
        }
    const TriangleMesh surface = catmullClarkSubdivide(grid, 2);
    ASSERT_EQ(surface.uvs.size(), surface.positions.size());
    for (size_t i = 0; i < surface.positions.size(); ++i) {
        EXPECT_EQ(surface.positions[i].z, 0.0f);
        EXPECT_NEAR(surface.normals[i].z, 1.0f, 1e-6f) << i;
    }
    // The four control corners are sharp: they stay; a boundary edge's midpoint vertex lies on the
    // boundary's cubic B-spline, which for a straight evenly spaced boundary is the line itself.
    for (Vec3f corner : {Vec3f{0, 0, 0}, Vec3f{3, 0, 0}, Vec3f{0, 3, 0}, Vec3f{3, 3, 0}}) {
        float distance;
        nearest(surface, corner, &distance);
        EXPECT_EQ(distance, 0.0f);
    }
    for (size_t i = 0; i < surface.positions.size(); ++i)
        if (surface.positions[i].y < 1e-6f) {
            EXPECT_EQ(surface.positions[i].y, 0.0f);
        }
}

// Triangles and a pentagon beside quads; uvs interpolated linearly over each control polygon (a
// vertex whose faces give it different uvs is split).
TEST(CatmullClark, PolygonsOfAnySizeAndFaceVaryingUvs) {
    // A pyramid over a pentagon: five triangles and the pentagon, facing out.
    PolygonMesh pyramid;
    for (int k = 0; k < 5; ++k)
        pyramid.positions.push_back(
            {float(std::cos(2 * M_PI * k / 5)), 0.0f, float(std::sin(2 * M_PI * k / 5))});
    pyramid.positions.push_back({0.0f, 1.0f, 0.0f});
    for (uint32_t k = 0; k < 5; ++k) {
        pyramid.faceSizes.push_back(3);
        pyramid.corners.insert(pyramid.corners.end(), {k, 5, (k + 1) % 5});
    }
    pyramid.faceSizes.push_back(5);
    pyramid.corners.insert(pyramid.corners.end(), {0, 1, 2, 3, 4});
    const TriangleMesh surface = catmullClarkSubdivide(pyramid, 2);
    EXPECT_EQ(surface.triangleCount(), (5u * 3u + 5u) * 4u * 2u);
    const Vec3f centre{0.0f, 0.4f, 0.0f};
    for (size_t i = 0; i < surface.positions.size(); ++i)
        EXPECT_GT(dot(surface.normals[i], surface.positions[i] - centre), 0.0f) << i;

    TriangleMesh flat = fanTriangulate(pyramid);
    EXPECT_EQ(flat.triangleCount(), 5u + 3u);
}

TEST(CatmullClark, Errors) {
    PolygonMesh fin = cube();
    // A seventh face on the edge (0, 2), which two faces already share.
    fin.positions.push_back({-2.0f, -2.0f, 0.0f});
    fin.faceSizes.push_back(3);
    fin.corners.insert(fin.corners.end(), {0, 2, 8});
    try {
        catmullClarkSubdivide(fin, 1);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("needs a manifold mesh"), std::string::npos) << e.what();
    }
    EXPECT_THROW(catmullClarkSubdivide(cube(), 0), InputError);
    EXPECT_THROW(catmullClarkSubdivide(cube(), 12), InputError);  // 24 corners: 48 * 4^11 triangles
}

}  // namespace
}  // namespace penumbra
