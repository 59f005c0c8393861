#include "scenes/scene_loader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "scenes/name_suggestion.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/shared_data.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using testing::catchInputError;

const fs::path kScenes = fs::path(PENUMBRA_TEST_DATA_DIR) / "scenes";
const fs::path kCornellBox = fs::path(PENUMBRA_SOURCE_DIR) / "scenes" / "cornell-box.json";
const fs::path kPbrtCornellBox = fs::path(PENUMBRA_DATA_DIR) / "cornell-box-bitterli" / "scene-v4.pbrt";

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

// The front normal of a triangle, from its winding.
Vec3f windingNormal(const TriangleMesh& mesh, size_t triangle) {
    const Vec3f p0 = mesh.positions[mesh.indices[3 * triangle]];
    const Vec3f p1 = mesh.positions[mesh.indices[3 * triangle + 1]];
    const Vec3f p2 = mesh.positions[mesh.indices[3 * triangle + 2]];
    return normalize(cross(p1 - p0, p2 - p0));
}

// A scene with one shape (and the material "m"), parsed as if it were kScenes/inline.json.
Scene sceneWithShape(const std::string& shapeJson) {
    return parseScene(R"({"materials": {"m": {"type": "lambert"}}, "shapes": [)" + shapeJson + "]}",
                      kScenes / "inline.json");
}

// ---- Good scenes ----

TEST(SceneLoader, ReadsEveryKey) {
    const Scene scene = loadScene(kScenes / "all_features.json");
    EXPECT_EQ(scene.sourcePath, kScenes / "all_features.json");
    // The mesh files, in the order the scene names them, for the scene hash.
    EXPECT_EQ(scene.meshFiles, (std::vector<std::filesystem::path>{kScenes / "meshes/square.obj",
                                                                   kScenes / "meshes/square_binary_le.ply"}));

    expectNear(scene.camera.lookFrom, {0, 1, 5});
    expectNear(scene.camera.lookAt, {0, 1, 0});
    expectNear(scene.camera.up, {0, 1, 0});
    EXPECT_FLOAT_EQ(scene.camera.verticalFovDegrees, 30.0f);
    EXPECT_FLOAT_EQ(scene.camera.apertureRadius, 0.05f);
    EXPECT_FLOAT_EQ(scene.camera.focusDistance, 4.5f);
    EXPECT_FLOAT_EQ(scene.camera.shutterOpen, 0.0f);
    EXPECT_FLOAT_EQ(scene.camera.shutterClose, 0.5f);

    EXPECT_EQ(scene.film.width, 320);
    EXPECT_EQ(scene.film.height, 240);
    EXPECT_EQ(scene.film.samplesPerPixel, 8);
    EXPECT_EQ(scene.film.filter, FilterKind::Box);
    EXPECT_FLOAT_EQ(scene.film.filterRadius, 0.5f);
    EXPECT_EQ(scene.integrator.maxDepth, 5);
    EXPECT_EQ(scene.integrator.rouletteStartDepth, 2);
    EXPECT_EQ(scene.integrator.strategy, LightStrategy::Light);
    EXPECT_EQ(scene.integrator.lightSampler, LightSampler::Power);
    EXPECT_EQ(scene.settings.sampler, SamplerKind::Independent);
    EXPECT_EQ(scene.settings.seed, 42u);
    EXPECT_FALSE(scene.settings.watertight);
    EXPECT_FALSE(scene.settings.canonicalHits);
    EXPECT_EQ(scene.environment.constantRadiance(), Rgb(0.1f, 0.2f, 0.3f));

    ASSERT_EQ(scene.materials.size(), 3u);  // in file order
    EXPECT_EQ(scene.materialNames[0], "white");
    EXPECT_EQ(scene.materials[0].albedo(), Rgb(0.8f));
    EXPECT_EQ(scene.materialNames[1], "red");
    EXPECT_EQ(scene.materials[1].albedo(), Rgb(0.9f, 0.1f, 0.1f));
    EXPECT_EQ(scene.materials[2].albedo(), Rgb(0.5f));  // the default

    ASSERT_EQ(scene.meshes.size(), 4u);
    const TriangleMesh& inlineMesh = scene.meshes[0];
    EXPECT_EQ(inlineMesh.name, "/shapes/0");
    EXPECT_EQ(inlineMesh.triangleCount(), 1u);
    expectNear(inlineMesh.normals[0], {0, 0, 1});  // [0, 0, 3], normalized
    EXPECT_FLOAT_EQ(inlineMesh.uvs[2].y, 1.0f);
    EXPECT_EQ(inlineMesh.material, 0u);
    EXPECT_FALSE(inlineMesh.emission.emits());

    const TriangleMesh& obj = scene.meshes[1];  // found relative to the scene's folder
    EXPECT_EQ(obj.name, "/shapes/1 (square.obj)");
    EXPECT_EQ(obj.triangleCount(), 2u);
    EXPECT_EQ(obj.material, 1u);
    expectNear(obj.positions[2], {1, 1, -1});  // translated by -1 in z

    EXPECT_EQ(scene.meshes[2].name, "/shapes/2 (square_binary_le.ply)");
    EXPECT_EQ(scene.meshes[2].triangleCount(), 3u);
    EXPECT_EQ(scene.meshes[2].material, 2u);

    const TriangleMesh& quad = scene.meshes[3];
    EXPECT_EQ(quad.triangleCount(), 2u);
    EXPECT_EQ(quad.emission.radiance, Rgb(4.0f));
    EXPECT_TRUE(quad.emission.twoSided);
    expectNear(windingNormal(quad, 0), {0, -1, 0});  // cross(edge1 = +x, edge2 = +z) = -y
    expectNear(windingNormal(quad, 1), {0, -1, 0});

    ASSERT_EQ(scene.spheres.size(), 1u);
    const Sphere& sphere = scene.spheres[0];
    EXPECT_EQ(sphere.name, "/shapes/4");
    expectNear(sphere.center, {1, 1, 0});  // scaled by 2, then moved by +1 in x
    EXPECT_FLOAT_EQ(sphere.radius, 1.0f);
    EXPECT_EQ(sphere.material, 1u);
    EXPECT_EQ(sphere.emission.radiance, Rgb(2.0f));
    EXPECT_FALSE(sphere.emission.twoSided);

    ASSERT_EQ(scene.lights.size(), 1u);
    const PointLight* point = std::get_if<PointLight>(&scene.lights[0]);
    ASSERT_NE(point, nullptr);
    expectNear(point->position, {0, 3, 0});
    EXPECT_EQ(point->intensity, Rgb(10.0f));
}

TEST(SceneLoader, EmptySceneIsValidAndUsesDefaults) {
    const Scene scene = loadScene(kScenes / "minimal.json");
    EXPECT_TRUE(scene.meshes.empty());
    EXPECT_TRUE(scene.spheres.empty());
    EXPECT_TRUE(scene.lights.empty());
    EXPECT_TRUE(scene.environment.isBlack());
    EXPECT_EQ(scene.film.width, FilmSettings{}.width);
    EXPECT_EQ(scene.film.samplesPerPixel, FilmSettings{}.samplesPerPixel);
    EXPECT_EQ(scene.integrator.strategy, LightStrategy::Mis);
    EXPECT_EQ(scene.integrator.lightSampler, LightSampler::Bvh);
    EXPECT_EQ(scene.integrator.maxDepth, IntegratorSettings{}.maxDepth);
    EXPECT_TRUE(scene.settings.watertight);
    EXPECT_TRUE(scene.settings.canonicalHits);
}

TEST(SceneLoader, CornellBox) {
    const Scene scene = loadScene(kCornellBox);
    expectNear(scene.camera.lookFrom, {0, 1, 6.8f});
    expectNear(scene.camera.lookAt, {0, 1, 0});
    expectNear(scene.camera.up, {0, 1, 0});
    EXPECT_FLOAT_EQ(scene.camera.verticalFovDegrees, 19.5f);
    EXPECT_EQ(scene.camera.apertureRadius, 0.0f);
    EXPECT_EQ(scene.film.width, 1024);
    EXPECT_EQ(scene.film.height, 1024);
    EXPECT_EQ(scene.film.samplesPerPixel, 64);
    EXPECT_EQ(scene.film.filter, FilterKind::Tent);
    EXPECT_FLOAT_EQ(scene.film.filterRadius, 1.0f);
    EXPECT_EQ(scene.integrator.maxDepth, 65);  // pbrt-v4 file: "integer maxdepth" [ 65 ]
    EXPECT_TRUE(scene.environment.isBlack());
    EXPECT_TRUE(scene.spheres.empty());
    EXPECT_TRUE(scene.lights.empty());

    ASSERT_EQ(scene.materials.size(), 8u);
    EXPECT_EQ(scene.materialNames[0], "LeftWall");
    EXPECT_EQ(scene.materials[0].albedo(), Rgb(0.63f, 0.065f, 0.05f));
    EXPECT_EQ(scene.materials[1].albedo(), Rgb(0.14f, 0.45f, 0.091f));
    EXPECT_EQ(scene.materialNames[7], "Light");
    EXPECT_TRUE(scene.materials[7].albedo().isBlack());

    ASSERT_EQ(scene.meshes.size(), 8u);
    size_t triangles = 0;
    for (const TriangleMesh& mesh : scene.meshes) triangles += mesh.triangleCount();
    EXPECT_EQ(triangles, 36u);

    // Exactly one emitter: the light quad, one-sided and facing down into the box.
    const TriangleMesh& light = scene.meshes.back();
    EXPECT_EQ(scene.materialNames[light.material], "Light");
    EXPECT_EQ(light.emission.radiance, Rgb(17, 12, 4));
    EXPECT_FALSE(light.emission.twoSided);
    ASSERT_EQ(light.triangleCount(), 2u);
    expectNear(windingNormal(light, 0), {0, -1, 0});
    expectNear(windingNormal(light, 1), {0, -1, 0});
    for (size_t i = 0; i + 1 < scene.meshes.size(); ++i) EXPECT_FALSE(scene.meshes[i].emission.emits()) << i;
}

// The numbers inside each `"NAME" [ ... ]` of a pbrt file, in order.
std::vector<std::vector<float>> pbrtArrays(const std::string& text, const std::string& name) {
    std::vector<std::vector<float>> arrays;
    const std::string key = "\"" + name + "\" [";
    for (size_t pos = text.find(key); pos != std::string::npos; pos = text.find(key, pos)) {
        pos += key.size();
        std::istringstream numbers(text.substr(pos, text.find(']', pos) - pos));
        std::vector<float> values;
        for (float v = 0; numbers >> v;) values.push_back(v);
        arrays.push_back(values);
    }
    return arrays;
}

// Each `KEYWORD "NAME"` of a pbrt file (not preceded by a letter), in order.
std::vector<std::string> pbrtNames(const std::string& text, const std::string& keyword) {
    std::vector<std::string> names;
    const std::string key = keyword + " \"";
    for (size_t pos = text.find(key); pos != std::string::npos; pos = text.find(key, pos + 1)) {
        if (pos > 0 && std::isalpha(static_cast<unsigned char>(text[pos - 1]))) continue;
        const size_t start = pos + key.size();
        names.push_back(text.substr(start, text.find('"', start) - start));
    }
    return names;
}

TEST(SceneLoader, CornellBoxMatchesThePbrtOriginal) {
    PENUMBRA_SKIP_WITHOUT_SHARED_DATA(kPbrtCornellBox);
    std::ifstream in(kPbrtCornellBox);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string pbrt = buffer.str();
    const Scene scene = loadScene(kCornellBox);

    const auto materialNames = pbrtNames(pbrt, "MakeNamedMaterial");
    const auto reflectances = pbrtArrays(pbrt, "rgb reflectance");
    ASSERT_EQ(materialNames.size(), scene.materials.size());
    ASSERT_EQ(reflectances.size(), scene.materials.size());
    for (size_t i = 0; i < materialNames.size(); ++i) {
        EXPECT_EQ(scene.materialNames[i], materialNames[i]);
        EXPECT_EQ(scene.materials[i].albedo(),
                  Rgb(reflectances[i][0], reflectances[i][1], reflectances[i][2]));
    }

    const auto meshMaterials = pbrtNames(pbrt, "NamedMaterial");
    const auto positions = pbrtArrays(pbrt, "point3 P");
    const auto indices = pbrtArrays(pbrt, "integer indices");
    ASSERT_EQ(positions.size(), scene.meshes.size());
    ASSERT_EQ(indices.size(), scene.meshes.size());
    ASSERT_EQ(meshMaterials.size(), scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        EXPECT_EQ(scene.materialNames[mesh.material], meshMaterials[m]);
        ASSERT_EQ(mesh.positions.size() * 3, positions[m].size()) << "mesh " << m;
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            for (int k = 0; k < 3; ++k)
                EXPECT_FLOAT_EQ(mesh.positions[i][k], positions[m][3 * i + size_t(k)]);
        ASSERT_EQ(mesh.indices.size(), indices[m].size()) << "mesh " << m;
        for (size_t i = 0; i < mesh.indices.size(); ++i) EXPECT_EQ(float(mesh.indices[i]), indices[m][i]);
    }
    EXPECT_EQ(pbrtArrays(pbrt, "rgb L").at(0), (std::vector<float>{17, 12, 4}));
}

TEST(SceneTransforms, TranslatedAndScaledQuadLandsWhereExpected) {
    // Scale by 2 first, then move by (1, 2, 3).
    Scene scene =
        sceneWithShape(R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "material": "m", "transform": [{"scale": 2}, {"translate": [1, 2, 3]}]})");
    ASSERT_EQ(scene.meshes.size(), 1u);
    const TriangleMesh& quad = scene.meshes[0];
    ASSERT_EQ(quad.positions.size(), 4u);
    expectNear(quad.positions[0], {1, 2, 3});
    expectNear(quad.positions[1], {3, 2, 3});
    expectNear(quad.positions[2], {3, 4, 3});
    expectNear(quad.positions[3], {1, 4, 3});
    expectNear(windingNormal(quad, 0), {0, 0, 1});

    // The other order moves first, so the move is scaled too.
    scene = sceneWithShape(R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "material": "m", "transform": [{"translate": [1, 2, 3]}, {"scale": [2, 2, 2]}]})");
    expectNear(scene.meshes[0].positions[0], {2, 4, 6});
}

TEST(SceneTransforms, MirrorKeepsTheFrontFace) {
    // A quad at z = 1 facing +z, mirrored in x: it still faces +z.
    const Scene scene =
        sceneWithShape(R"({"type": "quad", "corner": [0, 0, 1], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "material": "m", "transform": [{"scale": [-1, 1, 1]}]})");
    const TriangleMesh& quad = scene.meshes[0];
    expectNear(quad.positions[2], {-1, 1, 1});
    expectNear(windingNormal(quad, 0), {0, 0, 1});
    expectNear(windingNormal(quad, 1), {0, 0, 1});
}

TEST(SceneTransforms, RotateAndMatrix) {
    Scene scene =
        sceneWithShape(R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "material": "m", "transform": [{"rotate": {"axis": [0, 1, 0], "degrees": 90}}]})");
    expectNear(scene.meshes[0].positions[1], {0, 0, -1});  // +x turns to -z about +y
    expectNear(windingNormal(scene.meshes[0], 0), {1, 0, 0});

    scene = sceneWithShape(R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
        "material": "m", "transform": [{"matrix": [1, 0, 0, 5,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]}]})");
    expectNear(scene.meshes[0].positions[2], {6, 1, 0});  // row-major: the last column translates
}

TEST(SceneTransforms, InlineMeshNormalsAreTransformed) {
    const Scene scene = sceneWithShape(R"({"type": "triangle_mesh", "material": "m",
        "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, 2],
        "normals": [[0, 0, 1], [0, 0, 1], [0, 0, 1]], "transform": [{"scale": [1, 1, -1]}]})");
    const TriangleMesh& mesh = scene.meshes[0];
    for (const Vec3f& n : mesh.normals) expectNear(n, {0, 0, -1});
    expectNear(windingNormal(mesh, 0), {0, 0, -1});  // winding agrees with the mirrored normals
}

// A subdivision surface is refined at load (geometry/loop_subdivision.h has the scheme's tests):
// a tetrahedron's 4 triangles become 4 * 4^2, a transform applies to the refined surface.
TEST(SceneLoader, SubdivisionRefinesAMeshAtLoad) {
    const std::string tetrahedron = R"("positions": [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]],
        "indices": [0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2])";
    const Scene scene = sceneWithShape(R"({"type": "triangle_mesh", "material": "m", )" + tetrahedron +
                                       R"(, "subdivision": {"scheme": "loop", "levels": 2},
        "transform": [{"translate": [10, 0, 0]}]})");
    const TriangleMesh& mesh = scene.meshes[0];
    ASSERT_EQ(mesh.triangleCount(), 64u);
    // Vertex 0 keeps its index; its limit is (1, 1, 1) / 5 (the closed form of the scheme's test).
    expectNear(mesh.positions[0], {10.2f, 0.2f, 0.2f});

    InputError e = catchInputError([&] {
        sceneWithShape(R"({"type": "triangle_mesh", "material": "m", )" + tetrahedron +
                       R"(, "subdivision": {"scheme": "catmull"}})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/subdivision/scheme: expected one of: loop");
    e = catchInputError([&] {
        sceneWithShape(R"({"type": "triangle_mesh", "material": "m", )" + tetrahedron +
                       R"(, "subdivision": {"levels": 14}})");
    });
    EXPECT_CONTAINS(e.what(),
                    "/shapes/0/subdivision: 14 levels of subdivision would make more than 4194304 triangles");
    e = catchInputError([] {
        sceneWithShape(R"({"type": "triangle_mesh", "material": "m", "subdivision": {},
            "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]],
            "indices": [0, 1, 2, 1, 0, 3, 0, 1, 4]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/subdivision: Loop subdivision needs a manifold mesh");
}

// Polygons: "face_sizes" groups an inline mesh's indices (fans when not subdivided); Catmull-Clark
// surfaces of inline polygons and of an OBJ file's quads (read unsplit), their front by winding.
TEST(SceneLoader, PolygonsAndCatmullClarkSurfaces) {
    const std::string cube = R"("positions": [[-1, -1, -1], [1, -1, -1], [-1, 1, -1], [1, 1, -1],
                                              [-1, -1, 1], [1, -1, 1], [-1, 1, 1], [1, 1, 1]],
        "indices": [0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5],
        "face_sizes": [4, 4, 4, 4, 4, 4])";
    Scene scene = sceneWithShape(R"({"type": "triangle_mesh", "material": "m", )" + cube + "}");
    EXPECT_EQ(scene.meshes[0].triangleCount(), 12u);
    scene = sceneWithShape(R"({"type": "triangle_mesh", "material": "m", )" + cube +
                           R"(, "subdivision": {"scheme": "catmull_clark", "levels": 2}})");
    const TriangleMesh& rounded = scene.meshes[0];
    EXPECT_EQ(rounded.triangleCount(), 6u * 16u * 2u);
    ASSERT_EQ(rounded.normals.size(), rounded.positions.size());
    for (size_t t = 0; t < rounded.triangleCount(); ++t)
        EXPECT_GT(dot(windingNormal(rounded, t), rounded.positions[rounded.indices[3 * t]]), 0.0f) << t;

    const fs::path dir = fs::temp_directory_path() / "penumbra_polygon_file_test";
    fs::create_directories(dir);
    {
        std::ofstream obj(dir / "cube.obj");
        obj << "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n"
               "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    }
    for (const char* front : {"winding", "reversed"}) {
        scene = sceneWithShape(R"({"type": "mesh_file", "material": "m", "file": ")" +
                               (dir / "cube.obj").string() + R"(", "front": ")" + front +
                               R"(", "subdivision": {"scheme": "catmull_clark", "levels": 1}})");
        const TriangleMesh& mesh = scene.meshes[0];
        EXPECT_EQ(mesh.triangleCount(), 6u * 4u * 2u);
        const float side = std::string(front) == "winding" ? 1.0f : -1.0f;
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            EXPECT_GT(side * dot(windingNormal(mesh, t), mesh.positions[mesh.indices[3 * t]]), 0.0f) << front;
    }

    InputError e = catchInputError([&] {
        sceneWithShape(
            R"({"type": "triangle_mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
            "indices": [0, 1, 2], "face_sizes": [4]})");
    });
    EXPECT_CONTAINS(
        e.what(), "/shapes/0/face_sizes: the polygons have 4 corners in all, but \"indices\" has 3 entries");
    e = catchInputError([&] {
        sceneWithShape(R"({"type": "mesh_file", "material": "m", "file": ")" + (dir / "cube.obj").string() +
                       R"(", "front": "normals", "subdivision": {"scheme": "catmull_clark"}})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/front: a Catmull-Clark surface's front is given by its winding");
    e = catchInputError([&] {
        sceneWithShape(R"({"type": "triangle_mesh", "material": "m", )" + cube +
                       R"(, "subdivision": {"scheme": "catmull_clark", "levels": 0}})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/subdivision/levels");
}

// A mesh file's front side: its winding (the default), the other side, or pbrt-v4's rule, the
// side of the vertex normals (turned with the normals under ReverseOrientation). The file's one
// triangle winds to +z while its normals point to -z.
TEST(SceneLoader, AMeshFilesFrontIsItsWindingOrItsNormals) {
    const fs::path dir = fs::temp_directory_path() / "penumbra_mesh_front_test";
    fs::create_directories(dir);
    std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n";
    const struct {
        const char* front;
        Vec3f facing, normal;
    } cases[] = {{"winding", {0, 0, 1}, {0, 0, -1}},
                 {"reversed", {0, 0, -1}, {0, 0, 1}},
                 {"normals", {0, 0, -1}, {0, 0, -1}},
                 {"reversed_normals", {0, 0, 1}, {0, 0, 1}}};
    for (const auto& c : cases) {
        const Scene scene = sceneWithShape(R"({"type": "mesh_file", "material": "m", "file": ")" +
                                           (dir / "tri.obj").string() + R"(", "front": ")" + c.front + "\"}");
        SCOPED_TRACE(c.front);
        expectNear(windingNormal(scene.meshes[0], 0), c.facing);
        expectNear(scene.meshes[0].normals[0], c.normal);
    }
    const InputError e = catchInputError([&] {
        sceneWithShape(R"({"type": "mesh_file", "material": "m", "file": ")" + (dir / "tri.obj").string() +
                       R"(", "front": "back"})");
    });
    EXPECT_CONTAINS(e.what(),
                    "/shapes/0/front: expected one of: winding, reversed, normals, reversed_normals");
    fs::remove_all(dir);
}

double meshArea(const TriangleMesh& mesh) {
    double area = 0.0;
    for (size_t t = 0; t < mesh.triangleCount(); ++t)
        area += 0.5 *
                length(cross(mesh.positions[mesh.indices[3 * t + 1]] - mesh.positions[mesh.indices[3 * t]],
                             mesh.positions[mesh.indices[3 * t + 2]] - mesh.positions[mesh.indices[3 * t]]));
    return area;
}

// Cylinders and partial disks (pbrt-v4's cylinder, disk innerradius and phimax) are made of
// triangles as whole disks are: their vertices on the exact surface, their edges where the
// parameters put them, their area the exact one times the polygon's factor (for a step of a radians,
// a chord over its arc, sin(a / 2) / (a / 2), on a cylinder: 1 - 2.5e-5 at 256 steps a turn; a
// triangle over its sector, sin(a) / a, on a disk: 1 - 1.0e-4), their front where asked.
TEST(SceneLoader, CylindersAndPartialDisks) {
    const double pi = 3.14159265358979323846, step = 2.0 * pi / 256.0;
    const double polygon = std::sin(step / 2) / (step / 2), fan = std::sin(step) / step;
    {
        const Scene scene = sceneWithShape(R"({"type": "cylinder", "material": "m", "base": [1, 2, 3],
            "axis": [0, 0, 4], "radius": 0.5, "phi_max": 90, "start_direction": [0, 1, 0]})");
        const TriangleMesh& mesh = scene.meshes[0];
        ASSERT_EQ(mesh.triangleCount(), 2u * 64u);  // 90 degrees of 256 steps a turn
        float smallestX = 1e9f, largestY = -1e9f;
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3f d = mesh.positions[i] - Vec3f{1, 2, mesh.positions[i].z};
            EXPECT_NEAR(length(d), 0.5f, 1e-6f) << i;
            EXPECT_TRUE(mesh.positions[i].z == 3.0f || mesh.positions[i].z == 7.0f) << i;
            expectNear(mesh.normals[i], d * 2.0f);  // outward
            smallestX = std::min(smallestX, d.x), largestY = std::max(largestY, d.y);
        }
        // From +y (the start) a quarter turn counter-clockwise about +z: to -x.
        EXPECT_NEAR(smallestX, -0.5f, 1e-6f);
        EXPECT_NEAR(largestY, 0.5f, 1e-6f);
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Vec3f radial = mesh.normals[mesh.indices[3 * t]];
            EXPECT_GT(dot(windingNormal(mesh, t), radial), 0.99f) << t;
        }
        EXPECT_NEAR(meshArea(mesh), 0.5 * pi * 0.5 * 4.0 * polygon, 1e-5);
    }
    {
        const Scene scene = sceneWithShape(R"({"type": "cylinder", "material": "m", "base": [0, 0, 0],
            "axis": [0, 2, 0], "radius": 1, "front": "inside"})");
        const TriangleMesh& mesh = scene.meshes[0];
        EXPECT_NEAR(meshArea(mesh), 2.0 * pi * 2.0 * polygon, 1e-4);
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Vec3f p = mesh.positions[mesh.indices[3 * t]];
            EXPECT_LT(dot(windingNormal(mesh, t), Vec3f{p.x, 0, p.z}), 0.0f) << t;  // facing the axis
        }
        // The seam's vertices are the first ones again (watertight), with u = 1.
        EXPECT_EQ(mesh.positions[256], mesh.positions[0]);
        EXPECT_EQ(mesh.uvs[256].x, 1.0f);
    }
    {
        const Scene scene = sceneWithShape(R"({"type": "disk", "material": "m", "center": [0, 0, 1],
            "normal": [0, 0, -1], "radius": 2, "inner_radius": 1, "phi_max": 180})");
        const TriangleMesh& mesh = scene.meshes[0];
        ASSERT_EQ(mesh.triangleCount(), 2u * 128u);
        float nearest = 9.0f;
        for (const Vec3f& p : mesh.positions) {
            EXPECT_EQ(p.z, 1.0f);
            nearest = std::min(nearest, length(Vec3f{p.x, p.y, 0}));
        }
        EXPECT_NEAR(nearest, 1.0f, 1e-6f);
        for (size_t t = 0; t < mesh.triangleCount(); ++t) expectNear(windingNormal(mesh, t), {0, 0, -1});
        EXPECT_NEAR(meshArea(mesh), 0.5 * pi * (4.0 - 1.0) * fan, 1e-5);
    }
    InputError e = catchInputError([] {
        sceneWithShape(
            R"({"type": "disk", "material": "m", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1,
            "inner_radius": 1})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/inner_radius: expected an inner radius below the radius (1)");
    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "cylinder", "material": "m", "base": [0, 0, 0], "axis": [0, 0, 1], "radius": 1,
            "start_direction": [0, 0, 2]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/start_direction: expected a direction not parallel to the axis");
    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "cylinder", "material": "m", "base": [0, 0, 0], "axis": [0, 0, 1], "radius": 1,
            "phi_max": 0})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/phi_max: expected an angle above 0 degrees");
}

// ---- Bad input ----

// Spot lights: the cone from the axis to its edge and the falloff band inside it, in degrees
// (defaults pbrt-v4's 30 and 5); cos(30) and cos(25) worked out by hand.
// "alpha" on a shape or a prototype: a number in [0, 1] (1: opaque, no cut-out) or a texture; a
// sphere with one becomes triangles; an instance takes its prototype's.
TEST(SceneLoader, ShapeAlphaIsACutOut) {
    const Scene scene = parseScene(R"({"materials": {"m": {"type": "lambert"}},
        "prototypes": {"leaf": {"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
                                "alpha": {"type": "checkerboard", "colors": [1, 0]}}},
        "shapes": [
            {"type": "quad", "material": "m", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "alpha": 0.5},
            {"type": "quad", "material": "m", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "alpha": 1},
            {"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1, "alpha": 0.3},
            {"type": "instance", "material": "m", "prototype": "leaf"}]})",
                                   kScenes / "inline.json");
    ASSERT_EQ(scene.meshes.size(), 3u);
    ASSERT_TRUE(scene.meshes[0].alpha);
    EXPECT_FLOAT_EQ(scene.meshes[0].alpha->coverage({}), 0.5f);
    EXPECT_FALSE(scene.meshes[1].alpha);
    EXPECT_TRUE(scene.spheres.empty());
    ASSERT_TRUE(scene.meshes[2].alpha);
    EXPECT_FLOAT_EQ(scene.meshes[2].alpha->coverage({}), 0.3f);
    ASSERT_TRUE(scene.prototypes[0].alpha);
    EXPECT_EQ(scene.prototypes[0].alpha->kind(), TextureKind::Checkerboard);

    InputError e = catchInputError([] {
        sceneWithShape(R"({"type": "quad", "material": "m", "corner": [0, 0, 0], "edge1": [1, 0, 0],
            "edge2": [0, 1, 0], "alpha": 1.5})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/alpha");
    e = catchInputError([] {
        parseScene(R"({"materials": {"m": {"type": "lambert"}},
            "prototypes": {"p": {"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0]}},
            "shapes": [{"type": "instance", "material": "m", "prototype": "p", "alpha": 0.5}]})",
                   kScenes / "inline.json");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0");
    EXPECT_CONTAINS(e.what(), "alpha");
}

TEST(SceneLoader, SpotLights) {
    const Scene scene = parseScene(R"({"lights": [
        {"type": "spot", "position": [0, 3, 0], "direction": [0, -2, 0], "intensity": 10},
        {"type": "spot", "position": [1, 1, 1], "direction": [1, 0, 0], "intensity": [1, 2, 3], "cone_angle": 60, "cone_delta": 60}]})",
                                   "spots.json");
    ASSERT_EQ(scene.lights.size(), 2u);
    ASSERT_TRUE(std::holds_alternative<SpotLight>(scene.lights[0]) &&
                std::holds_alternative<SpotLight>(scene.lights[1]));
    const SpotLight& a = std::get<SpotLight>(scene.lights[0]);
    expectNear(a.position, {0, 3, 0});
    expectNear(a.direction, {0, -1, 0});
    EXPECT_EQ(a.intensity, Rgb(10.0f));
    EXPECT_NEAR(a.cosFalloffEnd, 0.8660254f, 1e-6f);
    EXPECT_NEAR(a.cosFalloffStart, 0.9063078f, 1e-6f);
    EXPECT_NEAR(std::get<SpotLight>(scene.lights[1]).cosFalloffEnd, 0.5f, 1e-6f);
    EXPECT_EQ(std::get<SpotLight>(scene.lights[1]).cosFalloffStart, 1.0f);
    for (
        const auto& [light, pointer, expected] :
        {std::tuple{R"({"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 0], "intensity": 1})",
                    "/lights/0/direction", "non-zero"},
         {R"({"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 1], "intensity": 1, "cone_angle": 0})",
          "/lights/0/cone_angle", "greater than 0"},
         {R"({"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 1], "intensity": 1, "cone_angle": 20, "cone_delta": 25})",
          "/lights/0/cone_delta", "cone_angle (20)"},
         {R"({"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 1], "intensity": 1, "angle": 20})",
          "/lights/0/angle", "cone_angle"}}) {
        const InputError e =
            catchInputError([&] { parseScene(std::string(R"({"lights": [)") + light + "]}", "spots.json"); });
        EXPECT_EQ(e.where().jsonPointer, pointer) << light;
        EXPECT_NE(std::string(e.message()).find(expected), std::string::npos) << e.message();
    }
}

TEST(SceneErrors, MissingSceneFile) {
    const fs::path file = kScenes / "no-such-scene.json";
    const InputError e = catchInputError([&] { loadScene(file); });
    EXPECT_EQ(e.where().file, file.string());
    EXPECT_CONTAINS(e.what(), "no-such-scene.json: scene file not found");
}

TEST(SceneErrors, SyntaxErrorHasLineAndColumn) {
    const InputError e = catchInputError([] { parseScene("{\n  \"film\": {\"spp\" 16}\n}", "broken.json"); });
    EXPECT_EQ(e.where().file, "broken.json");
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 19);  // the last character read: the end of the unexpected "16"
    EXPECT_CONTAINS(e.what(), "broken.json:2:19: syntax error");
    EXPECT_CONTAINS(e.what(), "expected ':'");
}

TEST(SceneErrors, UnknownKeys) {
    InputError e = catchInputError([] { parseScene(R"({"cameras": {}})", "scene.json"); });
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /cameras: unknown key (expected one of: camera, film, integrator, "
              "render, background, environment, materials, media, prototypes, shapes, lights); did you mean "
              "'camera'?");

    e = catchInputError([] {
        parseScene(R"({"materials": {"m": {"type": "lambert"}}, "shapes": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
            {"type": "sphere", "center": [0, 0, 0], "radus": 1, "material": "m"}]})",
                   "scene.json");
    });
    EXPECT_EQ(
        std::string(e.what()),
        "scene.json: /shapes/2/radus: unknown key (expected one of: type, center, radius, z_min, z_max, "
        "phi_max, start_direction, segments, material, alpha, emission, transform, motion, inside, outside); "
        "did "
        "you mean 'radius'?");

    e = catchInputError(
        [] { parseScene(R"({"film": {"filter": {"type": "box", "radius": 1, "width": 2}}})", "s.json"); });
    EXPECT_EQ(e.where().jsonPointer, "/film/filter/width");
}

TEST(SceneErrors, WrongTypes) {
    InputError e = catchInputError([] { parseScene(R"({"film": {"spp": "16"}})", "scene.json"); });
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /film/spp: expected an integer >= 1, found the string \"16\"");

    e = catchInputError([] { parseScene(R"({"camera": {"look_from": [0, 1]}})", "scene.json"); });
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /camera/look_from: expected an array of 3 numbers, found an array of 2 values");

    e = catchInputError([] { parseScene(R"({"shapes": {}})", "scene.json"); });
    EXPECT_EQ(std::string(e.what()), "scene.json: /shapes: expected an array, found an empty object");

    e = catchInputError([] { parseScene("[]", "scene.json"); });
    EXPECT_CONTAINS(e.what(), "scene.json: expected a JSON object");

    e = catchInputError(
        [] { sceneWithShape(R"({"type": "spher", "center": [0, 0, 0], "radius": 1, "material": "m"})"); });
    EXPECT_CONTAINS(
        e.what(), "/shapes/0/type: expected one of: triangle_mesh, mesh_file, quad, sphere, disk, cylinder");
}

// An unknown type or key gets a "did you mean": other renderers' names from a table that says
// whose they are, slips of spelling by edit distance, and nothing for a name that is not close.
TEST(SceneErrors, UnknownNamesGetTheLikelyOneSuggested) {
    InputError e =
        catchInputError([] { parseScene(R"({"materials": {"m": {"type": "diffuse"}}})", "s.json"); });
    EXPECT_EQ(
        std::string(e.what()),
        "s.json: /materials/m/type: expected one of: lambert, phong, dielectric, thin_dielectric, mirror, "
        "conductor, rough_conductor, rough_dielectric, coated_diffuse, coated_conductor, "
        "diffuse_transmission, hair, "
        "subsurface, measured, interface, mix, "
        "found the "
        "string "
        "\"diffuse\"; did you "
        "mean 'lambert'? (pbrt-v4 and Mitsuba 3 call it 'diffuse', Cycles 'Diffuse BSDF')");
    e = catchInputError([] { parseScene(R"({"materials": {"m": {"type": "roughconductor"}}})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "did you mean 'rough_conductor'? (Mitsuba 3 calls it 'roughconductor')");
    e = catchInputError([] { parseScene(R"({"materials": {"m": {"type": "emission"}}})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "a shape that emits light is any shape with an \"emission\" object");
    e = catchInputError(
        [] { parseScene(R"({"lights": [{"type": "distant", "direction": [0, -1, 0]}]})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "did you mean 'directional'? (pbrt-v4 calls it 'distant')");
    e = catchInputError([] { sceneWithShape(R"({"type": "trianglemesh", "positions": []})"); });
    EXPECT_CONTAINS(e.what(), "did you mean 'triangle_mesh'? (pbrt-v4 calls it 'trianglemesh')");
    // Slips: a letter missing, two swapped, another case.
    e = catchInputError([] { sceneWithShape(R"({"type": "spehre", "center": [0, 0, 0], "radius": 1})"); });
    EXPECT_CONTAINS(e.what(), "did you mean 'sphere'?");
    e = catchInputError([] { parseScene(R"({"film": {"Resolution": [4, 4]}})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "did you mean 'resolution'?");
    // A name that is not a slip of any accepted one gets the list only.
    e = catchInputError([] { parseScene(R"({"film": {"filter": {"type": "gauss"}}})", "s.json"); });
    EXPECT_EQ(std::string(e.what()).find("did you mean"), std::string::npos) << e.what();
    // A foreign name whose counterpart is not accepted here is not suggested.
    e = catchInputError([] { parseScene(R"({"film": {"filter": {"type": "diffuse"}}})", "s.json"); });
    EXPECT_EQ(std::string(e.what()).find("lambert"), std::string::npos) << e.what();
}

TEST(SceneErrors, NameDistanceCountsEditsIgnoringCaseAndSeparators) {
    EXPECT_EQ(nameDistance("rough_conductor", "RoughConductor"), 0);
    EXPECT_EQ(nameDistance("sphere", "spehre"), 1);  // a swap of neighbours is one edit
    EXPECT_EQ(nameDistance("radius", "radus"), 1);
    EXPECT_EQ(nameDistance("box", "tent"), 4);
    EXPECT_EQ(nameDistance("", "quad"), 4);
}

TEST(SceneErrors, UnknownMaterialListsTheKnownOnes) {
    InputError e = catchInputError([] {
        parseScene(R"({"materials": {"Floor": {"type": "lambert"}, "Wall": {"type": "lambert"}},
                       "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "Flor"}]})",
                   "scene.json");
    });
    EXPECT_EQ(e.where().jsonPointer, "/shapes/0/material");
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /shapes/0/material: unknown material \"Flor\" (known materials: Floor, Wall)");

    e = catchInputError([] {
        parseScene(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "x"}]})",
                   "s.json");
    });
    EXPECT_CONTAINS(e.what(), "the scene defines no materials");
}

TEST(SceneErrors, DuplicateMaterialName) {
    const InputError e = catchInputError([] {
        parseScene(R"({"materials": {"m": {"type": "lambert"}, "m": {"type": "lambert", "albedo": 1}}})",
                   "s.json");
    });
    EXPECT_EQ(e.where().jsonPointer, "/materials/m");
    EXPECT_CONTAINS(e.what(), "duplicate key");
}

TEST(SceneErrors, MissingMeshFileNamesTheFileAndTheShape) {
    const InputError e = catchInputError(
        [] { sceneWithShape(R"({"type": "mesh_file", "file": "meshes/nope.obj", "material": "m"})"); });
    EXPECT_EQ(e.where().file, (kScenes / "meshes/nope.obj").string());
    EXPECT_CONTAINS(e.what(), "nope.obj: mesh file not found");
    EXPECT_CONTAINS(e.what(), "inline.json: /shapes/0/file");
}

TEST(SceneErrors, MalformedMeshFileKeepsItsLine) {
    const InputError e = catchInputError(
        [] { sceneWithShape(R"({"type": "mesh_file", "file": "meshes/bad_number.obj", "material": "m"})"); });
    EXPECT_EQ(e.where().line, 3);
    EXPECT_CONTAINS(e.what(), "bad_number.obj:3:5: expected a number, found 'abc'");
    EXPECT_CONTAINS(e.what(), "/shapes/0/file");
}

TEST(SceneErrors, InlineMeshProblems) {
    InputError e = catchInputError([] {
        sceneWithShape(
            R"({"type": "triangle_mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
                           "indices": [0, 1, 2, 0, 2, 3, 1, 4, 2]})");
    });
    EXPECT_EQ(e.where().jsonPointer, "/shapes/0/indices/7");
    EXPECT_CONTAINS(e.what(), "/shapes/0/indices/7: index 4 is out of range: the mesh has 4 positions");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "triangle_mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1]})");
    });
    EXPECT_CONTAINS(e.what(),
                    "/shapes/0/indices: expected a non-empty array of vertex indices, 3 per triangle");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "triangle_mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                           "indices": [0, 1, 2], "normals": [[0, 0, 1]]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/normals: expected an array of 3 normals, one per position");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "triangle_mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, -2]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/indices/2: expected an integer >= 0, found -2");
}

TEST(SceneErrors, SppZero) {
    const InputError e = catchInputError([] { parseScene(R"({"film": {"spp": 0}})", "scene.json"); });
    EXPECT_EQ(std::string(e.what()), "scene.json: /film/spp: expected an integer >= 1, found 0");
}

TEST(SceneErrors, BadSensors) {
    auto error = [](const char* json) {
        return std::string(catchInputError([&] { parseScene(json, "scene.json"); }).what());
    };
    EXPECT_CONTAINS(error(R"({"film": {"sensor": {"iso": 0}}})"),
                    "scene.json: /film/sensor/iso: expected a number > 0");
    EXPECT_CONTAINS(error(R"({"film": {"sensor": {"exposure_time": -1}}})"), "/film/sensor/exposure_time");
    EXPECT_CONTAINS(
        error(R"({"film": {"sensor": {"white_balance": 500}}})"),
        "/film/sensor/white_balance: expected a colour temperature from 1000 to 100000 kelvin, or 0");
    EXPECT_CONTAINS(error(R"({"film": {"sensor": {"iso": 1e30, "exposure_time": 1e30}}})"),
                    "/film/sensor: exposure_time x iso / 100 must fit a 32-bit float");
    EXPECT_CONTAINS(error(R"({"film": {"sensor": {"gain": 2}}})"), "/film/sensor/gain: unknown key");
    const Scene scene =
        parseScene(R"({"film": {"sensor": {"iso": 200, "white_balance": 3200}}})", "scene.json");
    ASSERT_TRUE(scene.film.sensor);
    EXPECT_EQ(scene.film.sensor->imagingRatio(), 2.0f);
    EXPECT_EQ(scene.film.sensor->whiteBalance, 3200.0f);
    EXPECT_FALSE(parseScene("{}", "scene.json").film.sensor);
}

TEST(SceneErrors, UnknownLightStrategy) {
    const InputError e =
        catchInputError([] { parseScene(R"({"integrator": {"strategy": "photons"}})", "scene.json"); });
    EXPECT_CONTAINS(std::string(e.what()),
                    "scene.json: /integrator/strategy: expected one of: mis, bsdf, light");
}

TEST(SceneErrors, UnknownLightSampler) {
    const InputError e =
        catchInputError([] { parseScene(R"({"integrator": {"light_sampler": "uniform"}})", "scene.json"); });
    EXPECT_CONTAINS(std::string(e.what()),
                    "scene.json: /integrator/light_sampler: expected one of: bvh, power");
}

TEST(SceneErrors, ResolutionZero) {
    const InputError e =
        catchInputError([] { parseScene(R"({"film": {"resolution": [640, 0]}})", "scene.json"); });
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /film/resolution/1: expected an integer in [1, 65536], found 0");
}

TEST(SceneErrors, NegativeRadius) {
    const InputError e = catchInputError(
        [] { sceneWithShape(R"({"type": "sphere", "center": [0, 0, 0], "radius": -1, "material": "m"})"); });
    EXPECT_EQ(e.where().jsonPointer, "/shapes/0/radius");
    EXPECT_CONTAINS(e.what(), "/shapes/0/radius: expected a number > 0, found -1");
}

TEST(SceneErrors, SingularTransform) {
    InputError e = catchInputError([] {
        sceneWithShape(
            R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m",
                           "transform": [{"translate": [1, 0, 0]}, {"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  1, 1, 0, 0,  0, 0, 0, 1]}]})");
    });
    EXPECT_EQ(e.where().jsonPointer, "/shapes/0/transform/1/matrix");
    EXPECT_CONTAINS(e.what(), "the matrix is singular");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m",
                           "transform": [{"scale": [1, 0, 1]}]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/transform/0/scale: expected non-zero scale factors");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m",
                           "transform": [{"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 1, 1]}]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/transform/0/matrix: expected an affine matrix");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m",
                           "transform": [{"translate": [1, 0, 0], "scale": 2}]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/transform/0: expected an object with exactly one key");
}

// What the analytic sphere cannot be, triangles are: an ellipsoid (a sphere under a non-uniform
// scale) with its exact normals at the vertices, and part of a sphere (pbrt-v4's zmin, zmax,
// phimax) with its edges where the parameters put them and the area of its zone, 2 pi r h times
// the azimuth's share, less by the tessellation's 1.2e-4 (measured).
TEST(SceneLoader, EllipsoidsAndPartialSpheresAreMadeOfTriangles) {
    {
        const Scene scene =
            sceneWithShape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m",
            "transform": [{"scale": [1, 2, 3]}, {"translate": [5, 0, 0]}]})");
        ASSERT_TRUE(scene.spheres.empty());
        ASSERT_EQ(scene.meshes.size(), 1u);
        const TriangleMesh& mesh = scene.meshes[0];
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3f p = mesh.positions[i] - Vec3f{5, 0, 0};
            EXPECT_NEAR(p.x * p.x + p.y * p.y / 4 + p.z * p.z / 9, 1.0f, 1e-5f) << i;
            // The gradient of the ellipsoid's equation.
            expectNear(mesh.normals[i], normalize(Vec3f{p.x, p.y / 4, p.z / 9}), 1e-5f);
        }
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Vec3f p = mesh.positions[mesh.indices[3 * t]] - Vec3f{5, 0, 0};
            EXPECT_GT(dot(windingNormal(mesh, t), p), 0.0f) << t;  // outward
        }
    }
    {
        const Scene scene =
            sceneWithShape(R"({"type": "sphere", "center": [0, 0, 1], "radius": 2, "material": "m",
            "z_min": -1, "z_max": 2, "phi_max": 90})");
        ASSERT_EQ(scene.meshes.size(), 1u);
        const TriangleMesh& mesh = scene.meshes[0];
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3f p = mesh.positions[i] - Vec3f{0, 0, 1};
            EXPECT_NEAR(length(p), 2.0f, 1e-5f) << i;
            EXPECT_GE(p.z, -1.0f - 1e-5f) << i;
            EXPECT_GE(p.x, -1e-5f) << i;  // the first quadrant, counter-clockwise from +x
            EXPECT_GE(p.y, -1e-5f) << i;
        }
        double area = 0.0;
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            area += 0.5 * length(cross(
                              mesh.positions[mesh.indices[3 * t + 1]] - mesh.positions[mesh.indices[3 * t]],
                              mesh.positions[mesh.indices[3 * t + 2]] - mesh.positions[mesh.indices[3 * t]]));
        const double zone = 2.0 * 3.14159265358979323846 * 2.0 * 3.0 / 4.0;  // a quarter of 2 pi r h
        EXPECT_NEAR(area / zone, 1.0, 2e-4);
        EXPECT_LT(area / zone, 1.0);  // inscribed
    }
    // The coarsest: 3 segments a turn, two rings between the poles (a triangular bipyramid).
    EXPECT_EQ(sceneWithShape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m",
                  "phi_max": 360, "segments": 3, "transform": [{"scale": [1, 1, 2]}]})")
                  .meshes[0]
                  .triangleCount(),
              6u);
    const InputError e = catchInputError([] {
        sceneWithShape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m", "z_min": 0.5,
            "z_max": 0.5})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0: z_min (0.5) must be below z_max (0.5)");
}

TEST(SceneErrors, ValuesOutOfRange) {
    InputError e = catchInputError([] {
        sceneWithShape(R"({"type": "sphere", "center": [0, 1e39, 0], "radius": 1, "material": "m"})");
    });
    EXPECT_EQ(e.where().jsonPointer, "/shapes/0/center/1");
    EXPECT_CONTAINS(e.what(), "out of range (expected a finite 32-bit float)");

    e = catchInputError([] { parseScene(R"({"camera": {"fov": 180}})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "/camera/fov: expected a vertical field of view in degrees");

    e = catchInputError([] { parseScene(R"({"camera": {"shutter": [1, 0.5]}})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "/camera/shutter: expected [open, close] with close >= open");

    e = catchInputError(
        [] { parseScene(R"({"camera": {"look_from": [0, 0, 0], "look_at": [0, 0, 0]}})", "s.json"); });
    EXPECT_EQ(e.where().jsonPointer, "/camera");

    e = catchInputError([] {
        parseScene(R"({"materials": {"m": {"type": "lambert", "albedo": [0.5, 1.5, 0]}}})", "s.json");
    });
    EXPECT_CONTAINS(e.what(), "/materials/m/albedo/1: expected a number in [0, 1], found 1.5");

    e = catchInputError([] { parseScene(R"({"background": -1})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "/background: expected a number >= 0, found -1");

    e = catchInputError([] { parseScene(R"({"render": {"seed": 1.5}})", "s.json"); });
    EXPECT_CONTAINS(e.what(), "/render/seed: expected an integer >= 0, found 1.5");

    e = catchInputError([] { parseScene(R"({"render": {"watertight": 1}})", "s.json"); });
    EXPECT_EQ(e.where().jsonPointer, "/render/watertight");

    e = catchInputError([] { parseScene(R"({"render": {"canonical_hits": "yes"}})", "s.json"); });
    EXPECT_EQ(e.where().jsonPointer, "/render/canonical_hits");

    e = catchInputError([] {
        sceneWithShape(
            R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [2, 0, 0], "material": "m"})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0: edge1 and edge2 are zero or parallel");
}

}  // namespace
}  // namespace penumbra
