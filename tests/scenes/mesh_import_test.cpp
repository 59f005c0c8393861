#include "scenes/mesh_import.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/support/expect_input_error.h"
#include "tests/support/shared_data.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using testing::catchInputError;

const fs::path kMeshes = fs::path(PENUMBRA_TEST_DATA_DIR) / "scenes" / "meshes";
const fs::path kSharedData = PENUMBRA_DATA_DIR;

Vec3f corner(const TriangleMesh& mesh, size_t triangle, int k) {
    return mesh.positions[mesh.indices[3 * triangle + size_t(k)]];
}

// The front normal of a triangle, from its winding.
Vec3f windingNormal(const TriangleMesh& mesh, size_t triangle) {
    const Vec3f p0 = corner(mesh, triangle, 0);
    return normalize(cross(corner(mesh, triangle, 1) - p0, corner(mesh, triangle, 2) - p0));
}

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

// The 5-vertex, 3-triangle mesh of square_ascii.ply and its binary and gzip copies.
void expectSquareWithRoof(const TriangleMesh& mesh) {
    ASSERT_EQ(mesh.positions.size(), 5u);
    ASSERT_EQ(mesh.triangleCount(), 3u);
    expectNear(mesh.positions[2], {1, 1, 0});
    expectNear(mesh.positions[4], {0.5f, 0.5f, 1});
    // The quad face becomes two triangles covering the unit square, both facing +z.
    expectNear(windingNormal(mesh, 0), {0, 0, 1});
    expectNear(windingNormal(mesh, 1), {0, 0, 1});
    // The triangle (0 1 4) keeps its corners and order.
    EXPECT_EQ(mesh.indices[6], 0u);
    EXPECT_EQ(mesh.indices[7], 1u);
    EXPECT_EQ(mesh.indices[8], 4u);
}

TEST(MeshImport, ObjQuadIsTriangulated) {
    const TriangleMesh mesh = importMesh(kMeshes / "square.obj");
    EXPECT_EQ(mesh.name, "square.obj");
    ASSERT_EQ(mesh.positions.size(), 4u);
    ASSERT_EQ(mesh.triangleCount(), 2u);
    EXPECT_TRUE(mesh.normals.empty());
    EXPECT_TRUE(mesh.uvs.empty());
    expectNear(mesh.positions[0], {0, 0, 0});
    expectNear(mesh.positions[2], {1, 1, 0});
    expectNear(windingNormal(mesh, 0), {0, 0, 1});
    expectNear(windingNormal(mesh, 1), {0, 0, 1});
}

TEST(MeshImport, ObjNormalsAndUvsShareOneIndexBuffer) {
    const TriangleMesh mesh = importMesh(kMeshes / "square_normals_uvs.obj");
    ASSERT_EQ(mesh.positions.size(), 4u);  // 4 distinct (position, uv, normal) corners
    ASSERT_EQ(mesh.triangleCount(), 2u);
    ASSERT_EQ(mesh.normals.size(), 4u);
    ASSERT_EQ(mesh.uvs.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        expectNear(mesh.normals[i], {0, 0, 1});  // "vn 0 0 2", normalized
        // In the file, vt i belongs to v i and equals its x and y.
        EXPECT_FLOAT_EQ(mesh.uvs[i].x, mesh.positions[i].x);
        EXPECT_FLOAT_EQ(mesh.uvs[i].y, mesh.positions[i].y);
    }
    // The second face uses relative indices -4 -2 -1: vertices 1, 3, 4.
    expectNear(corner(mesh, 1, 0), {0, 0, 0});
    expectNear(corner(mesh, 1, 1), {1, 1, 0});
    expectNear(corner(mesh, 1, 2), {0, 1, 0});
}

TEST(MeshImport, ObjUvSeamsSplitVertices) {
    // Vertex 1 is used with two different uvs, so it becomes two vertices.
    const TriangleMesh mesh = importObj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
        "f 1/1 2/2 3/3\nf 1/4 3/3 2/2\n",
        "seam.obj");
    EXPECT_EQ(mesh.positions.size(), 4u);
    EXPECT_EQ(mesh.uvs.size(), 4u);
    EXPECT_TRUE(mesh.normals.empty());
    EXPECT_EQ(mesh.triangleCount(), 2u);
}

TEST(MeshImport, PlyAscii) { expectSquareWithRoof(importMesh(kMeshes / "square_ascii.ply")); }

TEST(MeshImport, PlyBinaryLittleEndianWithNormals) {
    const TriangleMesh mesh = importMesh(kMeshes / "square_binary_le.ply");
    expectSquareWithRoof(mesh);
    ASSERT_EQ(mesh.normals.size(), 5u);
    for (const Vec3f& n : mesh.normals) expectNear(n, {0, 0, 1});  // stored as (0, 0, 2)
}

TEST(MeshImport, PlyBinaryBigEndian) { expectSquareWithRoof(importMesh(kMeshes / "square_binary_be.ply")); }

TEST(MeshImport, GzipPly) {
    const TriangleMesh mesh = importMesh(kMeshes / "square.ply.gz");
    EXPECT_EQ(mesh.name, "square.ply.gz");
    expectSquareWithRoof(mesh);
}

TEST(MeshImport, SharedBunnyObj) {
    const fs::path file = kSharedData / "meshes" / "bunny-lowres.obj";
    PENUMBRA_SKIP_WITHOUT_SHARED_DATA(file);
    const TriangleMesh mesh = importMesh(file);
    EXPECT_EQ(mesh.triangleCount(), 3674u);
    EXPECT_EQ(mesh.positions.size(), 1839u);
    expectNear(mesh.positions[0], {1.301895f, 0.122622f, 2.550061f});
}

TEST(MeshImport, SharedCornellBoxObjWithMaterialsAndGroups) {
    // mtllib, usemtl and o lines are ignored: the scene file gives materials.
    const fs::path file = kSharedData / "cornell-box-embree" / "cornell_box.obj";
    PENUMBRA_SKIP_WITHOUT_SHARED_DATA(file);
    const TriangleMesh mesh = importMesh(file);
    EXPECT_EQ(mesh.triangleCount(), 34u);  // 17 quads
    EXPECT_EQ(mesh.positions.size(), 76u);
    expectNear(mesh.positions[0], {552.8f, 0, 0});
}

TEST(MeshImport, SharedDragonGzipPly) {
    const fs::path file = kSharedData / "meshes" / "dragon_vrip_res2.ply.gz";
    PENUMBRA_SKIP_WITHOUT_SHARED_DATA(file);
    const TriangleMesh mesh = importMesh(file);
    EXPECT_EQ(mesh.triangleCount(), 202520u);
    EXPECT_EQ(mesh.positions.size(), 100250u);
    expectNear(mesh.positions[0], {0.0321981f, 0.0565738f, -0.0503247f});
}

// ---- Bad input ----

TEST(MeshImportErrors, MissingFile) {
    const fs::path file = kMeshes / "no-such-mesh.obj";
    const InputError e = catchInputError([&] { importMesh(file); });
    EXPECT_EQ(e.where().file, file.string());
    EXPECT_CONTAINS(e.what(), "no-such-mesh.obj");
    EXPECT_CONTAINS(e.what(), "not found");
}

TEST(MeshImportErrors, UnsupportedExtension) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "../all_features.json"); });
    EXPECT_CONTAINS(e.what(), "all_features.json");
    EXPECT_CONTAINS(e.what(), "expected a name ending in .obj, .ply or .ply.gz");
}

TEST(MeshImportErrors, MalformedObjNumber) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "bad_number.obj"); });
    EXPECT_EQ(e.where().line, 3);
    EXPECT_EQ(e.where().column, 5);
    EXPECT_CONTAINS(e.what(), "bad_number.obj:3:5: expected a number, found 'abc'");
}

TEST(MeshImportErrors, MalformedObjFaces) {
    InputError e = catchInputError([] { importObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "zero.obj"); });
    EXPECT_EQ(e.where().line, 4);
    EXPECT_CONTAINS(e.what(), "index 0 is invalid (OBJ indices count from 1)");

    e = catchInputError([] { importObj("v 0 0 0\nv 1 0 0\nf 1 2\n", "two.obj"); });
    EXPECT_CONTAINS(e.what(), "two.obj:3:1: a face needs at least 3 vertices, found 2");

    e = catchInputError([] { importObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/x\n", "corner.obj"); });
    EXPECT_CONTAINS(e.what(), "corner.obj:4:7: expected a face corner");
    EXPECT_CONTAINS(e.what(), "found '3/x'");

    e = catchInputError([] { importObj("v 0 0\n", "short.obj"); });
    EXPECT_CONTAINS(e.what(), "short.obj:1:1: expected 3 to 6 numbers after 'v', found 2");
}

TEST(MeshImportErrors, ObjNanVertex) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "nan_vertex.obj"); });
    EXPECT_EQ(e.where().line, 4);
    EXPECT_CONTAINS(e.what(), "nan_vertex.obj:4:");
    EXPECT_CONTAINS(e.what(), "vertex 3 has a non-finite coordinate");
}

TEST(MeshImportErrors, ObjInfiniteVertexFromOverflow) {
    const InputError e =
        catchInputError([] { importObj("v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", "big.obj"); });
    EXPECT_CONTAINS(e.what(), "big.obj:2:3: vertex 2 has a non-finite coordinate (1e39)");
}

TEST(MeshImportErrors, ObjIndexOutOfRange) {
    InputError e = catchInputError([&] { importMesh(kMeshes / "index_out_of_range.obj"); });
    EXPECT_EQ(e.where().line, 7);
    EXPECT_CONTAINS(e.what(), "index_out_of_range.obj:7:");
    EXPECT_CONTAINS(e.what(), "vertex index 9 is out of range: the file has 4 vertices");

    e = catchInputError([] { importObj("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", "relative.obj"); });
    EXPECT_CONTAINS(e.what(), "relative.obj:3:");
    EXPECT_CONTAINS(e.what(), "relative vertex index -3 is out of range");
}

TEST(MeshImportErrors, ObjWithoutFacesIsEmpty) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "no_faces.obj"); });
    EXPECT_CONTAINS(e.what(), "no_faces.obj: the file contains no triangles");
}

TEST(MeshImportErrors, ObjZeroNormal) {
    const InputError e = catchInputError(
        [] { importObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n", "n.obj"); });
    EXPECT_CONTAINS(e.what(), "n.obj: normal 1 has zero length");
}

TEST(MeshImportErrors, MalformedPlyValue) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "bad_value.ply"); });
    EXPECT_EQ(e.where().line, 13);
    EXPECT_EQ(e.where().column, 3);
    EXPECT_CONTAINS(e.what(),
                    "bad_value.ply:13:3: expected a number for property 'y' of vertex 2, found 'abc'");
}

TEST(MeshImportErrors, MalformedPlyHeader) {
    InputError e = catchInputError([&] { importMesh(kMeshes / "no_end_header.ply"); });
    EXPECT_CONTAINS(e.what(), "no_end_header.ply: ");
    EXPECT_CONTAINS(e.what(), "no 'end_header' line");

    e = catchInputError([] { importPly("hello\n", "notply.ply"); });
    EXPECT_CONTAINS(e.what(), "notply.ply:1:1: not a PLY file");

    e = catchInputError(
        [] { importPly("ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\nend_header\n", "t.ply"); });
    EXPECT_CONTAINS(e.what(), "t.ply:4:1: unknown property type 'real'");

    e = catchInputError([] { importPly("", "empty.ply"); });
    EXPECT_CONTAINS(e.what(), "empty.ply: ");
}

TEST(MeshImportErrors, TruncatedPly) {
    // assimp 5.2 aborts, crashes or hangs on these; the validator must stop them first.
    InputError e = catchInputError([&] { importMesh(kMeshes / "truncated_ascii.ply"); });
    EXPECT_CONTAINS(e.what(), "truncated_ascii.ply:");
    EXPECT_CONTAINS(e.what(), "the file ends early (truncated?): face 1 of the 2 declared is incomplete");

    e = catchInputError([&] { importMesh(kMeshes / "truncated_binary.ply"); });
    EXPECT_CONTAINS(e.what(),
                    "truncated_binary.ply: the file ends early (truncated?): face 1 of the 2 declared");

    const std::string headerOnly =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n";
    e = catchInputError([&] { importPly(headerOnly + std::string(20, '\0'), "cut.ply"); });
    // Too short for its rows at all: refused from the header, before anything is allocated for them.
    EXPECT_CONTAINS(
        e.what(),
        "cut.ply: the file ends early (truncated?): the element 'vertex' declares 3 rows, which take "
        "at least 36 bytes, but the file holds 20 bytes after its header");
}

TEST(MeshImportErrors, TruncatedGzip) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "truncated.ply.gz"); });
    EXPECT_CONTAINS(e.what(), "truncated.ply.gz: ");
    EXPECT_CONTAINS(e.what(), "cannot decompress");
}

TEST(MeshImportErrors, PlyNanVertex) {
    InputError e = catchInputError([&] { importMesh(kMeshes / "nan_vertex.ply"); });
    EXPECT_CONTAINS(e.what(), "nan_vertex.ply: vertex 2 (counting from 0) has a non-finite coordinate");

    e = catchInputError([&] { importMesh(kMeshes / "nan_vertex_binary.ply"); });
    EXPECT_CONTAINS(e.what(),
                    "nan_vertex_binary.ply: vertex 2 (counting from 0) has a non-finite coordinate");
}

TEST(MeshImportErrors, PlyIndexOutOfRange) {
    const InputError e = catchInputError([&] { importMesh(kMeshes / "index_out_of_range.ply"); });
    EXPECT_CONTAINS(
        e.what(),
        "index_out_of_range.ply: face 1 (counting from 0) uses vertex 7, but the file has only 4 vertices");
}

TEST(MeshImportErrors, PlyWithoutFacesIsEmpty) {
    const InputError e = catchInputError([] {
        importPly(
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
            "end_header\n0 0 0\n",
            "points.ply");
    });
    EXPECT_CONTAINS(e.what(), "points.ply: the file contains no triangles");
}

// ---- Transforms ----

TriangleMesh unitTriangle() {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    mesh.indices = {0, 1, 2};
    return mesh;
}

TEST(MeshTransform, MovesPointsAndNormals) {
    TriangleMesh mesh = unitTriangle();
    // Scale x by 2 then shear-free rotate 90 degrees about x: +z turns into -y.
    transformMesh(mesh, Transform::rotate(90, {1, 0, 0}) * Transform::scale({2, 1, 1}));
    expectNear(mesh.positions[1], {2, 0, 0});
    expectNear(mesh.positions[2], {0, 0, 1});
    for (const Vec3f& n : mesh.normals) expectNear(n, {0, -1, 0});
    expectNear(windingNormal(mesh, 0), {0, -1, 0});
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(MeshTransform, NormalsUseTheInverseTransposeAndStayUnit) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
    const Vec3f n = normalize(Vec3f{0, -1, 1});  // the plane's normal
    mesh.normals = {n, n, n};
    mesh.indices = {0, 1, 2};
    transformMesh(mesh, Transform::scale({1, 1, 3}));  // a non-uniform scale tilts the plane
    const Vec3f expected =
        normalize(cross(mesh.positions[1] - mesh.positions[0], mesh.positions[2] - mesh.positions[0]));
    for (const Vec3f& normal : mesh.normals) expectNear(normal, expected);
}

TEST(MeshTransform, MirrorKeepsTheFrontFace) {
    TriangleMesh mesh = unitTriangle();
    transformMesh(mesh, Transform::scale({1, 1, -1}));  // mirror in z: the front now faces -z
    for (const Vec3f& n : mesh.normals) expectNear(n, {0, 0, -1});
    expectNear(windingNormal(mesh, 0), {0, 0, -1});  // winding swapped to agree
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 2, 1}));
}

}  // namespace
}  // namespace penumbra
