// Loop subdivision (geometry/loop_subdivision.h) against what the scheme guarantees: the limit of a
// regular tetrahedron's vertex in closed form, repeated refinement converging to the limit
// positions, limit positions that do not change when the mesh is refined further (the limit masks
// are the refinement's fixed points, so a wrong weight anywhere shows), limit normals against the
// finely refined surface, planes kept flat, the winding kept, uvs interpolated linearly across
// seams, and the errors.
#include "geometry/loop_subdivision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"

namespace penumbra {
namespace {

// A convex mesh around the origin with every triangle turned to face outward.
TriangleMesh outward(std::vector<Vec3f> positions, std::vector<uint32_t> indices) {
    TriangleMesh mesh;
    mesh.positions = std::move(positions);
    mesh.indices = std::move(indices);
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
        const Vec3f a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                    c = mesh.positions[mesh.indices[t + 2]];
        if (dot(cross(b - a, c - a), a + b + c) < 0.0f) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    }
    return mesh;
}

TriangleMesh tetrahedron() {
    return outward({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}}, {0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3});
}

TriangleMesh octahedron() {
    return outward({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                   {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5});
}

// A unit cube about the origin, each face split along one diagonal: valences 3 to 6.
TriangleMesh cube() {
    std::vector<Vec3f> p;
    for (int i = 0; i < 8; ++i)
        p.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
    return outward(std::move(p), {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                  2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5});
}

// An n x n grid of unit squares in the plane z = 0, two triangles each, facing +z: a mesh with a
// boundary.
TriangleMesh flatGrid(int n) {
    TriangleMesh mesh;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) mesh.positions.push_back({float(x), float(y), 0.0f});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    return mesh;
}

float distance(Vec3f a, Vec3f b) { return length(a - b); }

TEST(LoopSubdivision, ARegularTetrahedronsVertexHasItsLimitAtAFifth) {
    // Valence 3: beta = 3/16 and gamma = 1 / (3 + 3 / (8 beta)) = 1/5, so the limit of p is
    // (1 - 3/5) p + (1/5) (sum of the other three) = 2/5 p - 1/5 p = p / 5 (the four sum to 0). By
    // symmetry its normal is p's direction.
    const TriangleMesh control = tetrahedron();
    const TriangleMesh limit = loopSubdivide(control, 0);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_LT(distance(limit.positions[i], control.positions[i] * 0.2f), 1e-6f) << i;
        EXPECT_GT(dot(limit.normals[i], normalize(control.positions[i])), 1.0f - 1e-6f) << i;
    }
}

TEST(LoopSubdivision, RepeatedRefinementConvergesToTheLimitPositions) {
    const TriangleMesh control = tetrahedron();
    const Vec3f target = control.positions[0] * 0.2f;
    float previous = distance(control.positions[0], target);
    for (int levels = 1; levels <= 4; ++levels) {
        const float error = distance(refineLoop(control, levels).positions[0], target);
        // Measured: the error shrinks by 1/16 per level (the tetrahedron's symmetry leaves only that
        // mode), until float rounding; a wrong weight anywhere converges elsewhere.
        EXPECT_LT(error, 0.07f * previous) << levels;
        previous = error;
    }
    EXPECT_LT(previous, 3e-5f);
}

// The limit of every vertex of the mesh refined `levels` times, against the limit of the same vertex
// (the same index: refinement keeps vertex indices) after one level more.
void expectLimitsUnchangedByRefinement(const TriangleMesh& control, int levels) {
    const TriangleMesh coarse = loopSubdivide(control, levels);
    const TriangleMesh fine = loopSubdivide(control, levels + 1);
    float worstPosition = 0.0f, worstNormal = 0.0f;
    for (size_t i = 0; i < coarse.positions.size(); ++i) {
        worstPosition = std::max(worstPosition, distance(coarse.positions[i], fine.positions[i]));
        worstNormal = std::max(worstNormal, distance(coarse.normals[i], fine.normals[i]));
    }
    // Measured: the positions identical, the normals within 2e-7 (float rounding of the masks);
    // the limit mask 1% off moves them by 2e-4 to 6e-3 at these levels (measured on the cube and
    // the octahedron).
    EXPECT_LT(worstPosition, 2e-6f) << "levels " << levels;
    EXPECT_LT(worstNormal, 2e-5f) << "levels " << levels;
}

TEST(LoopSubdivision, LimitPositionsAndNormalsDoNotChangeWhenRefinedFurther) {
    for (int levels = 0; levels <= 2; ++levels) {
        expectLimitsUnchangedByRefinement(cube(), levels);
        expectLimitsUnchangedByRefinement(octahedron(), levels);
        expectLimitsUnchangedByRefinement(tetrahedron(), levels);
    }
}

TEST(LoopSubdivision, BoundaryLimitsDoNotChangeWhenRefinedFurther) {
    // The grid's boundary vertices take the boundary rules (valence 2 to 4 at the corners and
    // edges), its inner vertices valence 6.
    for (int levels = 0; levels <= 2; ++levels) expectLimitsUnchangedByRefinement(flatGrid(3), levels);
}

TEST(LoopSubdivision, AFlatMeshStaysFlatWithTheNormalOfItsPlane) {
    const TriangleMesh limit = loopSubdivide(flatGrid(4), 3);
    ASSERT_EQ(limit.triangleCount(), 32u * 64u);
    for (size_t i = 0; i < limit.positions.size(); ++i) {
        EXPECT_EQ(limit.positions[i].z, 0.0f) << i;
        EXPECT_GT(limit.normals[i].z, 1.0f - 1e-6f) << i;
    }
}

TEST(LoopSubdivision, LimitNormalsAgreeWithTheFinelyRefinedSurface) {
    // The normal of the surface refined 6 levels, from the triangles around each level-1 vertex (they
    // keep their indices), against the limit normal computed at level 1, on a box of three different
    // sides whose diagonals break every symmetry (on a regular solid symmetry alone would make the
    // normals agree). Measured: within 0.04 degrees; the level-1 mesh's own normals (its triangles'
    // around each vertex) are up to 2.2 degrees off, so 0.2 degrees tells the limit masks apart.
    std::vector<Vec3f> corners;
    for (int i = 0; i < 8; ++i)
        corners.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.5f : -1.0f, i & 4 ? 0.7f : -1.0f});
    const TriangleMesh control =
        outward(std::move(corners), {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                     2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5});
    const TriangleMesh limit = loopSubdivide(control, 1);
    const TriangleMesh fine = refineLoop(control, 6);
    std::vector<Vec3f> around(limit.positions.size(), Vec3f{0, 0, 0});
    for (size_t t = 0; t < fine.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k)
            if (fine.indices[t + k] < around.size()) {
                const Vec3f a = fine.positions[fine.indices[t]], b = fine.positions[fine.indices[t + 1]],
                            c = fine.positions[fine.indices[t + 2]];
                around[fine.indices[t + k]] += cross(b - a, c - a);
            }
    for (size_t i = 0; i < limit.positions.size(); ++i) {
        const float cosine = dot(normalize(around[i]), limit.normals[i]);
        EXPECT_GT(cosine, std::cos(0.2f * 3.14159265f / 180.0f)) << i;
    }
}

TEST(LoopSubdivision, TrianglesKeepTheSideTheirWindingFaces) {
    const TriangleMesh limit = loopSubdivide(cube(), 2);
    for (size_t t = 0; t < limit.indices.size(); t += 3) {
        const Vec3f a = limit.positions[limit.indices[t]], b = limit.positions[limit.indices[t + 1]],
                    c = limit.positions[limit.indices[t + 2]];
        const Vec3f n = cross(b - a, c - a);
        EXPECT_GT(dot(n, a + b + c), 0.0f) << t / 3;  // outward, as the cube's
        for (int k = 0; k < 3; ++k) EXPECT_GT(dot(n, limit.normals[limit.indices[t + k]]), 0.0f) << t / 3;
    }
}

TEST(LoopSubdivision, UvsAreInterpolatedLinearlyOverEachControlTriangle) {
    TriangleMesh square;
    square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    square.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    square.indices = {0, 1, 2, 0, 2, 3};
    const TriangleMesh refined = refineLoop(square, 2);
    ASSERT_EQ(refined.triangleCount(), 32u);
    ASSERT_EQ(refined.uvs.size(), refined.positions.size());
    // Two levels of midpoints over the control triangles: the uvs are the 5 x 5 lattice of quarters.
    std::vector<std::pair<float, float>> uvs;
    for (Vec2f uv : refined.uvs) uvs.push_back({uv.x, uv.y});
    std::sort(uvs.begin(), uvs.end());
    uvs.erase(std::unique(uvs.begin(), uvs.end()), uvs.end());
    ASSERT_EQ(uvs.size(), 25u);
    for (size_t i = 0; i < 25; ++i) {
        EXPECT_EQ(uvs[i].first, float(i / 5) * 0.25f);
        EXPECT_EQ(uvs[i].second, float(i % 5) * 0.25f);
    }
}

TEST(LoopSubdivision, VerticesSplitAtUvSeamsAreOneVertexOfTheSurface) {
    // The cube with a vertex per face corner (as a mesh file with per-face uvs gives it) is the
    // same closed surface as the cube with shared vertices.
    const TriangleMesh shared = cube();
    TriangleMesh split;
    for (size_t i = 0; i < shared.indices.size(); ++i) {
        split.positions.push_back(shared.positions[shared.indices[i]]);
        split.uvs.push_back({float(i % 3) * 0.5f, float(i / 3) * 0.1f});
        split.indices.push_back(uint32_t(i));
    }
    const TriangleMesh a = loopSubdivide(shared, 2), b = loopSubdivide(split, 2);
    ASSERT_EQ(a.triangleCount(), b.triangleCount());
    for (size_t t = 0; t < a.indices.size(); ++t) {
        EXPECT_LT(distance(a.positions[a.indices[t]], b.positions[b.indices[t]]), 1e-6f) << t;
        EXPECT_LT(distance(a.normals[a.indices[t]], b.normals[b.indices[t]]), 1e-6f) << t;
    }
}

TEST(LoopSubdivision, RefusesAnEdgeOfThreeTrianglesAndMoreTrianglesThanTheInputAllows) {
    TriangleMesh fin;
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    fin.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    try {
        refineLoop(fin, 1);
        FAIL() << "a non-manifold edge was refined";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("the edge between vertices 0 and 1 is shared by 3 triangles"),
                  std::string::npos)
            << e.what();
    }
    // The refined triangles are bounded by the input: 4^5 a control triangle, at least 2^22, at
    // most 2^26 (core/input_limits.h). The check comes before any refinement.
    auto refusal = [](const TriangleMesh& mesh, int levels) {
        try {
            refineLoop(mesh, levels);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("refined");
    };
    EXPECT_EQ(refineLoop(tetrahedron(), 10).triangleCount(), 4u << 20);  // 2^22: allowed
    EXPECT_NE(refusal(tetrahedron(), 11)
                  .find("11 levels of subdivision would make more than 4194304 triangles "
                        "of the 4 given"),
              std::string::npos)
        << refusal(tetrahedron(), 11);
    EXPECT_NE(refusal(flatGrid(64), 6).find("more than 8388608 triangles of the 8192 given"),
              std::string::npos);
    EXPECT_NE(refusal(flatGrid(256), 5).find("more than 67108864 triangles of the 131072 given"),
              std::string::npos);
    EXPECT_THROW(refineLoop(tetrahedron(), -1), InputError);
}

}  // namespace
}  // namespace penumbra
