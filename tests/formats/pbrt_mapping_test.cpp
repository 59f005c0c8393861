// What each pbrt-v4 directive becomes in penumbra's scene (formats/pbrt/scene_builder.h,
// materials.h, spectrum.h), checked on the converted document and on the built Scene. Expected
// values come from pbrt-v4's definitions (cameras.cpp, lights.cpp, materials.cpp), worked out by
// hand in the comments.
#include <OpenEXR/ImfRgbaFile.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "cameras/camera.h"
#include "core/colorimetry.h"
#include "core/equal_area.h"
#include "core/error.h"
#include "formats/pbrt/double_math.h"
#include "formats/pbrt/pbrt_reader.h"
#include "formats/pbrt/spectrum.h"
#include "formats/scene_file.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"

namespace penumbra::pbrt {
namespace {

namespace fs = std::filesystem;

// A camera that needs no mirroring: pbrt's LookAt frame mirrored by Scale -1 1 1 is the
// right-handed frame penumbra's camera uses.
const std::string kCamera =
    "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n";

PbrtConversion convert(const std::string& text) { return convertPbrtText(text, "test.pbrt"); }

Json matrixOf(const Json& shape) { return shape.at("transform").at(0).at("matrix"); }

bool hasWarning(const PbrtConversion& c, const std::string& part) {
    for (const std::string& w : c.warnings)
        if (w.find(part) != std::string::npos) return true;
    return false;
}

TEST(PbrtMapping, DefaultsArePbrtV4s) {
    const auto c = convert("WorldBegin\n");
    EXPECT_EQ(c.document["film"]["resolution"], Json::array({1280, 720}));
    EXPECT_EQ(c.document["film"]["spp"], 16);
    EXPECT_EQ(c.document["integrator"]["max_depth"], 5);
    EXPECT_DOUBLE_EQ(c.document["camera"]["fov"].get<double>(), 90.0);  // the shorter (vertical) axis
    EXPECT_TRUE(hasWarning(c, "no PixelFilter"));
}

TEST(PbrtMapping, FovIsTheShorterAxisAndTheScreenWindowScalesIt) {
    auto portrait = convert(
        kCamera + "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 200\nWorldBegin\n");
    const double expected =
        2.0 * std::atan(std::tan(20.0 * std::numbers::pi / 180.0) * 2.0) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(portrait.document["camera"]["fov"].get<double>(), expected, 1e-9);
    auto window =
        convert(kCamera +
                "Camera \"perspective\" \"float fov\" 40 \"float screenwindow\" [-0.5 0.5 -0.5 0.5]\n"
                "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 100\nWorldBegin\n");
    const double halved =
        2.0 * std::atan(std::tan(20.0 * std::numbers::pi / 180.0) * 0.5) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(window.document["camera"]["fov"].get<double>(), halved, 1e-9);
    auto lens =
        convert("Camera \"perspective\" \"float lensradius\" 0.1 \"float focaldistance\" 7\nWorldBegin\n");
    EXPECT_DOUBLE_EQ(lens.document["camera"]["aperture_radius"].get<double>(), 0.1);
    EXPECT_DOUBLE_EQ(lens.document["camera"]["focus_distance"].get<double>(), 7.0);
}

// pbrt-v4's spherical camera: the world direction it gives a pixel (its GenerateRay written out:
// the equirectangular theta = pi t, phi = 2 pi s, or the equal-area square, then y and z swapped),
// from the camera frame of kCamera (camera x, y, z = world x, y, -z), against penumbra's camera
// built from the converted file, on both mappings and on and off the image's centre lines.
TEST(PbrtMapping, SphericalCameraSeesWhatPbrtsSees) {
    for (const char* mapping : {"equirectangular", "equalarea"}) {
        const std::string text =
            "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"spherical\" \"string mapping\" \"" +
            std::string(mapping) +
            "\"\nFilm \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 64\nWorldBegin\n";
        const auto c = convert(text);
        EXPECT_EQ(c.document["camera"]["type"], "spherical");
        const Scene scene = buildPbrtScene(c, "test.pbrt");
        const Camera camera(scene.camera, 64, 64);
        for (Vec2f st : {Vec2f{0.1f, 0.3f}, Vec2f{0.3f, 0.8f}, Vec2f{0.55f, 0.45f}, Vec2f{0.9f, 0.6f}}) {
            Vec3f cameraSpace;
            if (std::string(mapping) == "equirectangular") {
                const float theta = kPi * st.y, phi = 2.0f * kPi * st.x;
                cameraSpace = {std::sin(theta) * std::cos(phi), std::cos(theta),
                               std::sin(theta) * std::sin(phi)};
            } else {
                const Vec3f abc = equalAreaSquareToSphere(st);
                cameraSpace = {abc.x, abc.z, abc.y};
            }
            const Vec3f expected{cameraSpace.x, cameraSpace.y, -cameraSpace.z};
            const Vec3f seen =
                camera.generateRay({st.x * 64.0f, st.y * 64.0f}, {0.5f, 0.5f}, 0.0f).ray.direction;
            EXPECT_NEAR(seen.x, expected.x, 1e-5f) << mapping << " " << st.x << "," << st.y;
            EXPECT_NEAR(seen.y, expected.y, 1e-5f) << mapping << " " << st.x << "," << st.y;
            EXPECT_NEAR(seen.z, expected.z, 1e-5f) << mapping << " " << st.x << "," << st.y;
        }
    }
}

TEST(PbrtMapping, OrthographicAndRealisticCameras) {
    // The default screen window of a 2:1 film is [-2, 2] x [-1, 1]: 2 units high.
    auto ortho =
        convert(kCamera +
                "Camera \"orthographic\" \"float lensradius\" 0.1 \"float focaldistance\" 3\n"
                "Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\nWorldBegin\n");
    EXPECT_EQ(ortho.document["camera"]["type"], "orthographic");
    EXPECT_DOUBLE_EQ(ortho.document["camera"]["height"].get<double>(), 2.0);
    EXPECT_DOUBLE_EQ(ortho.document["camera"]["aperture_radius"].get<double>(), 0.1);
    const std::string lens = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/lenses/wide.22mm.dat";
    auto realistic =
        convert(kCamera + "Camera \"realistic\" \"string lensfile\" \"" + lens +
                "\" \"float aperturediameter\" 5 \"float focusdistance\" 3 \"string aperture\" \"star\"\n"
                "Film \"rgb\" \"float diagonal\" 43.3\nWorldBegin\n");
    const Json& camera = realistic.document["camera"];
    EXPECT_EQ(camera["type"], "lens_system");
    EXPECT_EQ(camera["lens_file"], lens);
    EXPECT_DOUBLE_EQ(camera["aperture_diameter"].get<double>(), 5.0);
    EXPECT_DOUBLE_EQ(camera["focus_distance"].get<double>(), 3.0);
    EXPECT_DOUBLE_EQ(camera["film_diagonal"].get<double>(), 43.3);
    EXPECT_EQ(camera["aperture"], "star");
    EXPECT_FALSE(hasWarning(realistic, "not supported"));
    const Scene scene = buildPbrtScene(realistic, "test.pbrt");
    EXPECT_EQ(scene.camera.lensSystem.surfaces.size(), 13u);
    const InputError missing = testing::catchInputError(
        [&] { convert(kCamera + "Camera \"realistic\" \"string lensfile\" \"no-such.dat\"\nWorldBegin\n"); });
    EXPECT_CONTAINS(missing.what(), "no-such.dat");
    EXPECT_CONTAINS(missing.what(), "test.pbrt:");
}

TEST(PbrtMapping, LookAtIsLeftHandedSoTheWorldIsMirrored) {
    // pbrt's LookAt from +z: camera +x (the image's right) is world -x. penumbra's camera looking
    // the same way has world +x on the right, so the world is mirrored across the plane x = 0.
    auto c = convert(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nTranslate 1 0 0\nShape "
        "\"sphere\"\n");
    EXPECT_EQ(c.document["camera"]["look_from"], Json::array({0.0, 0.0, 5.0}));
    EXPECT_DOUBLE_EQ(matrixOf(c.document["shapes"][0])[3].get<double>(), -1.0);
    // With the Scale -1 1 1 idiom nothing is mirrored.
    auto idiom = convert(kCamera + "WorldBegin\nTranslate 1 0 0\nShape \"sphere\"\n");
    EXPECT_DOUBLE_EQ(matrixOf(idiom.document["shapes"][0])[3].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(matrixOf(idiom.document["shapes"][0])[0].get<double>(), 1.0);
}

TEST(PbrtMapping, TransformsComposeInPbrtsOrder) {
    // Translate then Scale: points are scaled first, then moved.
    auto c = convert(kCamera +
                     "WorldBegin\nTranslate 1 0 0\nScale 2 2 2\nShape \"sphere\"\n"
                     "Identity\nRotate 90 0 0 1\nShape \"sphere\"\n"
                     "Transform [1 0 0 0  0 1 0 0  0 0 1 0  4 5 6 1]\nConcatTransform [2 0 0 0  0 2 0 0  0 0 "
                     "2 0  0 0 0 1]\n"
                     "Shape \"sphere\"\n");
    const Json m0 = matrixOf(c.document["shapes"][0]);
    EXPECT_EQ(m0,
              Json::array({2.0, 0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0}));
    const Json m1 = matrixOf(c.document["shapes"][1]);  // x -> y
    EXPECT_NEAR(m1[4].get<double>(), 1.0, 1e-12);
    EXPECT_NEAR(m1[1].get<double>(), -1.0, 1e-12);
    const Json m2 = matrixOf(c.document["shapes"][2]);  // the matrix's last four numbers are the translation
    EXPECT_EQ(m2,
              Json::array({2.0, 0.0, 0.0, 4.0, 0.0, 2.0, 0.0, 5.0, 0.0, 0.0, 2.0, 6.0, 0.0, 0.0, 0.0, 1.0}));
}

TEST(PbrtMapping, AttributesTransformBlocksAndCoordinateSystems) {
    auto c = convert(
        kCamera +
        "WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n"
        "AttributeBegin\nTranslate 1 0 0\nMaterial \"conductor\"\nCoordinateSystem \"moved\"\nAttributeEnd\n"
        "Shape \"sphere\"\n"
        "TransformBegin\nTranslate 0 2 0\nMaterial \"dielectric\"\nTransformEnd\nShape \"sphere\"\n"
        "CoordSysTransform \"moved\"\nShape \"sphere\"\n");
    const Json& shapes = c.document["shapes"];
    EXPECT_FALSE(shapes[0].contains("transform"));
    EXPECT_EQ(c.document["materials"][shapes[0]["material"].get<std::string>()]["type"], "lambert");
    // TransformEnd restores the transform only: the dielectric stays.
    EXPECT_FALSE(shapes[1].contains("transform"));
    EXPECT_EQ(c.document["materials"][shapes[1]["material"].get<std::string>()]["type"], "dielectric");
    EXPECT_DOUBLE_EQ(matrixOf(shapes[2])[3].get<double>(), 1.0);
    EXPECT_TRUE(
        hasWarning(convert("WorldBegin\nCoordSysTransform \"nowhere\"\n"), "unknown coordinate system"));
}

TEST(PbrtMapping, ReverseOrientationAndNormalsChooseTheFrontFace) {
    const std::string quad =
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0] \"integer indices\" [0 1 2]";
    auto plain = convert(kCamera + "WorldBegin\n" + quad + "\n");
    EXPECT_EQ(plain.document["shapes"][0]["indices"], Json::array({0, 1, 2}));
    auto reversed = convert(kCamera + "WorldBegin\nReverseOrientation\n" + quad + "\n");
    EXPECT_EQ(reversed.document["shapes"][0]["indices"], Json::array({0, 2, 1}));
    // Normals pointing to -z turn the front to -z (pbrt-v4 faces the geometric normal to them).
    auto normals = convert(kCamera + "WorldBegin\n" + quad + " \"normal N\" [0 0 -1 0 0 -1 0 0 -1]\n");
    EXPECT_EQ(normals.document["shapes"][0]["indices"], Json::array({0, 2, 1}));
    // A mirroring transform keeps a triangle's front (the loader swaps the winding with it), but
    // turns a disk's (pbrt-v4 flips the normals of quadrics then).
    // A PLY mesh faces its file's normals, the other way under ReverseOrientation (the loader's
    // "front": tests/scenes/scene_loader_test.cpp).
    const std::string ply =
        "Shape \"plymesh\" \"string filename\" \"" +
        (fs::path(PENUMBRA_SOURCE_DIR) / "tests/data/scenes/meshes/square_ascii.ply").string() + "\"\n";
    EXPECT_EQ(convert(kCamera + "WorldBegin\n" + ply).document["shapes"][0]["front"], "normals");
    EXPECT_EQ(convert(kCamera + "WorldBegin\nReverseOrientation\n" + ply).document["shapes"][0]["front"],
              "reversed_normals");
    auto disk = convert(kCamera + "WorldBegin\nScale 1 1 -1\nShape \"disk\" \"float height\" 2\n");
    EXPECT_EQ(disk.document["shapes"][0]["normal"], Json::array({0.0, 0.0, -1.0}));
    EXPECT_EQ(disk.document["shapes"][0]["center"], Json::array({0.0, 0.0, 2.0}));
}

TEST(PbrtMapping, ObjectInstancesArePrototypesAndInstances) {
    // Two meshes with their own materials (pbrt-v4: the material current inside the definition),
    // the object placed twice, the second time moving (ActiveTransform EndTime).
    const std::string tri =
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n";
    auto c = convert(
        kCamera +
        "WorldBegin\nMakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0 0]\n"
        "ObjectBegin \"pair\"\nNamedMaterial \"red\"\n" +
        tri + "AttributeBegin\nMaterial \"diffuse\"\nTranslate 0 0 2\n" + tri +
        "AttributeEnd\nObjectEnd\n"
        "Material \"conductor\"\nTranslate 3 0 0\nObjectInstance \"pair\"\n"
        "ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\nObjectInstance \"pair\"\n");
    const Json& prototypes = c.document["prototypes"];
    ASSERT_EQ(prototypes.size(), 2u);
    EXPECT_FALSE(prototypes["pair/0"].contains("transform"));
    EXPECT_DOUBLE_EQ(matrixOf(prototypes["pair/1"])[11].get<double>(),
                     2.0);  // the shape's own Translate, baked in
    const Json& shapes = c.document["shapes"];
    ASSERT_EQ(shapes.size(), 4u);
    EXPECT_EQ(shapes[0]["type"], "instance");
    EXPECT_EQ(shapes[0]["prototype"], "pair/0");
    EXPECT_EQ(shapes[0]["material"], "red");
    EXPECT_EQ(shapes[1]["prototype"], "pair/1");
    EXPECT_NE(shapes[1]["material"], "red");
    // The diffuse material of the definition, not the conductor current at ObjectInstance.
    EXPECT_EQ(c.document["materials"][shapes[1]["material"].get<std::string>()]["type"], "lambert");
    EXPECT_DOUBLE_EQ(matrixOf(shapes[0])[3].get<double>(), 3.0);
    const Json& keys = shapes[2]["motion"]["transforms"];
    ASSERT_EQ(keys.size(), 2u);
    EXPECT_DOUBLE_EQ(keys[0]["translate"][0].get<double>(), 3.0);
    EXPECT_DOUBLE_EQ(keys[1]["translate"][0].get<double>(), 4.0);
    EXPECT_FALSE(hasWarning(c, "copies"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    EXPECT_EQ(scene.prototypes.size(), 2u);
    ASSERT_EQ(scene.instances.size(), 4u);
    EXPECT_TRUE(scene.instances[3].moves());
    EXPECT_NEAR(scene.instances[1].placement.applyPoint(scene.prototypes[1].positions[0]).z, 2.0, 1e-6);
}

TEST(PbrtMapping, ObjectSpheresAndEmittersArePlacedAsCopies) {
    auto c =
        convert(kCamera +
                "WorldBegin\nObjectBegin \"ball\"\nTranslate 0 1 0\nShape \"sphere\" \"float radius\" 0.5\n"
                "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"disk\"\nObjectEnd\n"
                "Translate 3 0 0\nObjectInstance \"ball\"\nTranslate 3 0 0\nObjectInstance \"ball\"\n");
    EXPECT_FALSE(c.document.contains("prototypes"));
    const Json& shapes = c.document["shapes"];
    ASSERT_EQ(shapes.size(), 4u);
    EXPECT_EQ(shapes[0]["type"], "sphere");
    EXPECT_DOUBLE_EQ(matrixOf(shapes[0])[3].get<double>(), 3.0);
    EXPECT_DOUBLE_EQ(matrixOf(shapes[0])[7].get<double>(), 1.0);
    EXPECT_TRUE(shapes[1].contains("emission"));
    EXPECT_DOUBLE_EQ(matrixOf(shapes[2])[3].get<double>(), 6.0);
    EXPECT_TRUE(hasWarning(
        c, "object instances of spheres (penumbra's prototypes are meshes) are placed as copies (2 times)"));
    EXPECT_TRUE(hasWarning(
        c, "object instances of area lights (instances do not emit) are placed as copies (2 times)"));
}

TEST(PbrtMapping, ActiveTransformGivesMotionKeys) {
    auto c =
        convert(kCamera +
                "WorldBegin\nActiveTransform EndTime\nTranslate 2 0 0\nRotate 90 0 1 0\nActiveTransform All\n"
                "Shape \"sphere\"\n");
    const Json& keys = c.document["shapes"][0]["motion"]["transforms"];
    ASSERT_EQ(keys.size(), 2u);
    EXPECT_DOUBLE_EQ(keys[0]["rotate"]["degrees"].get<double>(), 0.0);
    EXPECT_NEAR(keys[1]["rotate"]["degrees"].get<double>(), 90.0, 1e-9);
    EXPECT_NEAR(keys[1]["rotate"]["axis"][1].get<double>(), 1.0, 1e-9);
    EXPECT_DOUBLE_EQ(keys[1]["translate"][0].get<double>(), 2.0);
    EXPECT_EQ(c.document["camera"]["shutter"], Json::array({0.0, 1.0}));
    // It builds: the loader accepts the keys over the open shutter.
    EXPECT_TRUE(buildPbrtScene(c, "test.pbrt").spheres[0].motion.moves());
}

TEST(PbrtMapping, Materials) {
    auto c = convert(
        kCamera +
        "WorldBegin\n"
        "MakeNamedMaterial \"d\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.2 0.4 0.6]\n"
        "MakeNamedMaterial \"c\" \"string type\" \"conductor\" \"float roughness\" 0.25\n"
        "MakeNamedMaterial \"a\" \"string type\" \"conductor\" \"float uroughness\" 0.1 \"float vroughness\" "
        "0.2 "
        "\"bool remaproughness\" false \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n"
        "MakeNamedMaterial \"r\" \"string type\" \"conductor\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
        "MakeNamedMaterial \"g\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n"
        "MakeNamedMaterial \"t\" \"string type\" \"thindielectric\" \"float eta\" 1.33\n"
        "MakeNamedMaterial \"p\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" [0.5 0.1 0.1] \"float "
        "roughness\" 0.04\n"
        "MakeNamedMaterial \"i\" \"string type\" \"interface\"\n"
        "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"d\" \"g\"] \"float amount\" "
        "0.8\n"
        "Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [0.3 0.3 0.3]\n"
        "Texture \"s\" \"spectrum\" \"scale\" \"texture tex\" \"k\" \"float scale\" 2\n"
        "MakeNamedMaterial \"x\" \"string type\" \"diffuse\" \"texture reflectance\" \"s\"\n"
        "MakeNamedMaterial \"shade\" \"string type\" \"diffusetransmission\" \"rgb transmittance\" [0.5 0.6 "
        "0.7] "
        "\"float scale\" 1.5\n"
        "Texture \"cb\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [0.2 0.2 0.2] \"rgb tex2\" [0.4 0.4 0.4]\n"
        "MakeNamedMaterial \"leaf\" \"string type\" \"diffusetransmission\" \"texture reflectance\" "
        "\"cb\"\n");
    const Json& m = c.document["materials"];
    EXPECT_EQ(m["d"], Json::parse(R"({"type": "lambert", "albedo": [0.2, 0.4, 0.6]})"));
    // remaproughness (the default): alpha = sqrt(roughness); copper by default.
    EXPECT_EQ(m["c"]["type"], "rough_conductor");
    EXPECT_DOUBLE_EQ(m["c"]["alpha"].get<double>(), 0.5);
    EXPECT_NEAR(m["c"]["eta"][0].get<double>(), 0.200438, 1e-6);
    EXPECT_EQ(m["a"]["alpha"], Json::array({0.1, 0.2}));
    EXPECT_NEAR(m["a"]["k"][0].get<double>(), 3.98316, 1e-5);
    // reflectance 0.5: eta 1, k = 2 sqrt(0.5) / sqrt(0.5) = 2 gives ((1-1)^2 + k^2) / ((1+1)^2 + k^2) = 0.5.
    EXPECT_EQ(m["r"]["type"], "conductor");
    EXPECT_EQ(m["r"]["reflectance"], Json::parse("[0.5, 0.5, 0.5]"));
    EXPECT_NEAR(m["g"]["eta"].get<double>(), 1.5168, 1e-6);
    EXPECT_EQ(m["t"]["type"], "thin_dielectric");
    EXPECT_EQ(m["p"]["type"], "coated_diffuse");
    EXPECT_DOUBLE_EQ(m["p"]["alpha"].get<double>(), 0.2);
    EXPECT_EQ(m["i"], Json::parse(R"({"type": "interface"})"));
    EXPECT_EQ(m["m"], Json::parse(R"({"type": "mix", "materials": ["d", "g"], "amount": 0.8})"));
    EXPECT_NEAR(m["x"]["albedo"][0].get<double>(), 0.6, 1e-6);
    EXPECT_FALSE(hasWarning(c, "mix"));
    // diffusetransmission: reflectance and transmittance (0.25 each) times scale, clamped to 1.
    EXPECT_EQ(m["shade"]["type"], "diffuse_transmission");
    EXPECT_EQ(m["shade"]["reflectance"], Json::parse("[0.375, 0.375, 0.375]"));
    for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(m["shade"]["transmittance"][ch].get<double>(), std::min(1.0, 1.5 * (0.5 + 0.1 * ch)),
                    1e-6);
    EXPECT_EQ(m["leaf"]["reflectance"]["type"], "checkerboard");
    EXPECT_EQ(m["leaf"]["transmittance"], Json::parse("[0.25, 0.25, 0.25]"));
    EXPECT_FALSE(hasWarning(c, "diffusetransmission"));
    EXPECT_FALSE(hasWarning(c, "transmittance"));
    // The whole scene builds.
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    EXPECT_EQ(scene.materials.size(), m.size());
}

// pbrt-v4's subsurface material (materials.cpp SubsurfaceMaterial::Create): its four ways of
// giving the interior, eta 1.33 by default, the roughness as a dielectric's, and its errors.
// pbrt-v4's coateddiffuse and coatedconductor (materials.cpp, their Create): the layered model
// with the file's interface, base, slab and walk; coatedconductor's "reflectance" has no prefix.
TEST(PbrtMapping, LayeredMaterials) {
    const auto c =
        convert(kCamera +
                "WorldBegin\n"
                "MakeNamedMaterial \"plastic\" \"string type\" \"coateddiffuse\" "
                "\"rgb reflectance\" [0.2 0.3 0.4] \"float roughness\" 0.01 \"float thickness\" 0.05 "
                "\"rgb albedo\" [0.5 0.5 0.5] \"float g\" 0.3 \"integer maxdepth\" 20 "
                "\"integer nsamples\" 2\n"
                "MakeNamedMaterial \"paint\" \"string type\" \"coatedconductor\" "
                "\"float interface.eta\" 1.7 \"float interface.roughness\" 0.04 "
                "\"rgb conductor.eta\" [0.2 0.9 1.1] \"rgb conductor.k\" [3.9 2.4 1.8] "
                "\"float conductor.uroughness\" 0.09 \"float conductor.vroughness\" 0.16\n"
                "Texture \"thin\" \"float\" \"checkerboard\" \"float tex1\" 0.01 \"float tex2\" 0.5\n"
                "MakeNamedMaterial \"chrome\" \"string type\" \"coatedconductor\" "
                "\"rgb reflectance\" [0.9 0.8 0.7] \"texture thickness\" \"thin\"\n"
                "Material \"coatedconductor\"\n"
                "Shape \"sphere\"\n");
    const Json& m = c.document["materials"];
    EXPECT_EQ(m["plastic"]["type"], "coated_diffuse");
    EXPECT_EQ(m["plastic"]["model"], "layered");
    EXPECT_DOUBLE_EQ(m["plastic"]["alpha"].get<double>(), 0.1);  // remaproughness: sqrt
    EXPECT_DOUBLE_EQ(m["plastic"]["thickness"].get<double>(), 0.05);
    EXPECT_EQ(m["plastic"]["medium_albedo"], Json::parse("[0.5, 0.5, 0.5]"));
    EXPECT_DOUBLE_EQ(m["plastic"]["g"].get<double>(), 0.3);
    EXPECT_EQ(m["plastic"]["max_depth"], 20);
    EXPECT_EQ(m["plastic"]["samples"], 2);
    EXPECT_EQ(m["paint"]["type"], "coated_conductor");
    EXPECT_DOUBLE_EQ(m["paint"]["eta"].get<double>(), 1.7);
    EXPECT_DOUBLE_EQ(m["paint"]["alpha"].get<double>(), 0.2);
    EXPECT_NEAR(m["paint"]["conductor"]["eta"][1].get<double>(), 0.9, 1e-6);
    EXPECT_NEAR(m["paint"]["conductor"]["k"][0].get<double>(), 3.9, 1e-6);
    EXPECT_NEAR(m["paint"]["conductor"]["alpha"][0].get<double>(), 0.3, 1e-6);
    EXPECT_NEAR(m["paint"]["conductor"]["alpha"][1].get<double>(), 0.4, 1e-6);
    EXPECT_DOUBLE_EQ(m["paint"]["thickness"].get<double>(), 0.01);  // pbrt-v4's default
    EXPECT_NEAR(m["chrome"]["conductor"]["reflectance"][2].get<double>(), 0.7, 1e-6);
    EXPECT_EQ(m["chrome"]["thickness"]["type"], "checkerboard");
    EXPECT_FALSE(hasWarning(c, "coated"));
    EXPECT_FALSE(hasWarning(c, "reflectance"));
    // pbrt-v4's default coatedconductor: copper under a smooth coat of index 1.5.
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    const auto& copper = std::get<LayeredBsdf>(scene.materials.back().model());
    EXPECT_EQ(copper.base, LayeredBsdf::Base::Conductor);
    EXPECT_FLOAT_EQ(copper.eta, 1.5f);
    EXPECT_GT(copper.conductorK.r, 2.0f);
    EXPECT_EQ(copper.coatDistribution.alphaX, 0.0f);
}

// pbrt-v4's subsurface coefficients as textures: the texture objects themselves (evaluated where a
// walk enters), no warning.
TEST(PbrtMapping, TexturedSubsurfaceCoefficients) {
    const auto c =
        convert(kCamera +
                "WorldBegin\n"
                "Texture \"cb\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [0.2 0.2 0.2] \"rgb tex2\" "
                "[0.4 0.4 0.4]\n"
                "MakeNamedMaterial \"jade\" \"string type\" \"subsurface\" \"texture reflectance\" \"cb\" "
                "\"texture mfp\" \"cb\"\n"
                "MakeNamedMaterial \"wax\" \"string type\" \"subsurface\" \"texture sigma_a\" \"cb\" "
                "\"rgb sigma_s\" [1 2 3]\n"
                "Material \"subsurface\"\n"
                "Shape \"sphere\"\n");
    const Json& m = c.document["materials"];
    EXPECT_EQ(m["jade"]["reflectance"]["type"], "checkerboard");
    EXPECT_EQ(m["jade"]["mfp"]["type"], "checkerboard");
    EXPECT_EQ(m["wax"]["sigma_a"]["type"], "checkerboard");
    EXPECT_EQ(m["wax"]["sigma_s"], Json::parse("[1.0, 2.0, 3.0]"));
    EXPECT_FALSE(hasWarning(c, "texture"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    EXPECT_TRUE(scene.materials[0].isTextured());
}

// pbrt-v4's PixelSensor (film.cpp, PixelSensor::Create): the imaging ratio from the film's iso and
// the camera's shutter time, the film's white balance, and a measured sensor's default 6500 K.
TEST(PbrtMapping, FilmSensor) {
    auto sensorOf = [](const std::string& film, const std::string& camera) {
        const auto c = convert(film + camera + "WorldBegin\nShape \"sphere\"\n");
        return c.document["film"].contains("sensor") ? c.document["film"]["sensor"] : Json();
    };
    const std::string camera = "Camera \"perspective\"\n";
    EXPECT_TRUE(sensorOf("", camera).is_null());  // shutter 0 to 1, iso 100: the radiance itself
    EXPECT_EQ(sensorOf("Film \"rgb\" \"float iso\" 400 \"float whitebalance\" 3000\n",
                       "Camera \"perspective\" \"float shutteropen\" 0.25 \"float shutterclose\" 0.75\n"),
              Json::parse(R"({"iso": 400.0, "exposure_time": 0.5, "white_balance": 3000.0})"));
    const auto c = convert("Film \"rgb\" \"string sensor\" \"canon_eos_100d\"\n" + camera +
                           "WorldBegin\nShape \"sphere\"\n");
    EXPECT_EQ(c.document["film"]["sensor"], Json::parse(R"({"white_balance": 6500.0})"));
    EXPECT_TRUE(hasWarning(c, "Film sensor \"canon_eos_100d\": its measured response is not in penumbra"));
    EXPECT_CONTAINS(testing::catchInputError([&] {
                        convert("Film \"rgb\" \"float iso\" -5\n" + camera + "WorldBegin\n");
                    }).what(),
                    "Film: iso must be > 0");
}

TEST(PbrtMapping, MeasuredMaterials) {
    const auto c = convert(kCamera +
                           "WorldBegin\n"
                           "Material \"measured\" \"string filename\" \"bsdfs/gold.bsdf\"\n"
                           "Shape \"sphere\"\n");
    EXPECT_EQ(c.document["materials"].begin().value(),
              Json::parse(R"({"type": "measured", "filename": "bsdfs/gold.bsdf"})"));
    EXPECT_FALSE(hasWarning(c, "measured"));
    EXPECT_CONTAINS(testing::catchInputError([&] {
                        convert(kCamera + "WorldBegin\nMaterial \"measured\"\nShape \"sphere\"\n");
                    }).what(),
                    "test.pbrt:5:1: a measured material needs its .bsdf file as \"string filename\"");
}

TEST(PbrtMapping, SubsurfaceMaterials) {
    auto c =
        convert(kCamera +
                "WorldBegin\n"
                "MakeNamedMaterial \"skin\" \"string type\" \"subsurface\" \"string name\" \"Skin1\" "
                "\"float scale\" 10 \"float g\" 0.5\n"
                "MakeNamedMaterial \"wax\" \"string type\" \"subsurface\" \"rgb sigma_a\" [0.1 0.2 0.3] "
                "\"rgb sigma_s\" [1 2 3] \"float eta\" 1.5 \"float roughness\" 0.04\n"
                "MakeNamedMaterial \"jade\" \"string type\" \"subsurface\" \"rgb reflectance\" [0.3 0.7 0.4] "
                "\"rgb mfp\" [0.5 1 0.5]\n"
                "MakeNamedMaterial \"milk\" \"string type\" \"subsurface\"\n"
                "Material \"subsurface\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
                "Shape \"sphere\"\n");
    const Json& m = c.document["materials"];
    EXPECT_EQ(m["skin"],
              Json::parse(R"({"type": "subsurface", "eta": 1.33, "scale": 10.0, "preset": "Skin1"})"));
    EXPECT_TRUE(hasWarning(c, "\"g\" is ignored with named scattering coefficients"));
    EXPECT_EQ(m["wax"]["sigma_a"], Json::parse("[0.1, 0.2, 0.3]"));
    EXPECT_EQ(m["wax"]["sigma_s"], Json::parse("[1.0, 2.0, 3.0]"));
    EXPECT_DOUBLE_EQ(m["wax"]["eta"].get<double>(), 1.5);
    EXPECT_DOUBLE_EQ(m["wax"]["alpha"].get<double>(), 0.2);  // remaproughness: sqrt(0.04)
    EXPECT_EQ(m["jade"]["mfp"], Json::parse("[0.5, 1.0, 0.5]"));
    EXPECT_NEAR(m["jade"]["reflectance"][1].get<double>(), 0.7, 1e-6);
    EXPECT_EQ(m["milk"], Json::parse(R"({"type": "subsurface", "eta": 1.33})"));
    EXPECT_FALSE(hasWarning(c, "subsurface"));
    // It builds: one interior medium per subsurface material, inside the sphere.
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    EXPECT_EQ(scene.media.size(), 5u);
    ASSERT_EQ(scene.spheres.size(), 1u);
    EXPECT_TRUE(scene.isMaterialInterior(scene.spheres[0].media.inside));

    const InputError unknown = testing::catchInputError(
        [] { convert(kCamera + "WorldBegin\nMaterial \"subsurface\" \"string name\" \"Jelly\"\n"); });
    EXPECT_CONTAINS(unknown.what(), "test.pbrt:");
    EXPECT_CONTAINS(unknown.what(), "unknown measured medium \"Jelly\"");
    const InputError half = testing::catchInputError(
        [] { convert(kCamera + "WorldBegin\nMaterial \"subsurface\" \"rgb sigma_a\" [1 1 1]\n"); });
    EXPECT_CONTAINS(half.what(), "a subsurface material with \"sigma_a\" needs \"sigma_s\" too");
    const InputError path = testing::catchInputError([] {
        convert(kCamera +
                "WorldBegin\nMaterial \"subsurface\" \"rgb reflectance\" [1 1 1] \"float mfp\" 0\n");
    });
    EXPECT_CONTAINS(path.what(),
                    "parameter \"mfp\" (the mean free path) must be > 0 and finite in every channel");
}

// pbrt-v4's spot light (lights.cpp SpotLight::Create): from, to, coneangle (30), conedelta (5);
// "power" divides by 2 pi ((1 - cos(25)) + (cos(25) - cos(30)) / 2) = 0.715236 for the defaults.
TEST(PbrtMapping, SpotLights) {
    auto c = convert(kCamera +
                     "WorldBegin\nTranslate 0 1 0\n"
                     "LightSource \"spot\" \"rgb I\" [1 2 3] \"point3 from\" [0 2 0] \"point3 to\" [0 0 0] "
                     "\"float coneangle\" 40 \"float conedelta\" 10\n"
                     "LightSource \"spot\" \"float power\" 10\n");
    const Json& lights = c.document["lights"];
    EXPECT_EQ(lights[0]["type"], "spot");
    EXPECT_EQ(lights[0]["position"], Json::array({0.0, 3.0, 0.0}));
    EXPECT_EQ(lights[0]["direction"], Json::array({0.0, -1.0, 0.0}));
    EXPECT_EQ(lights[0]["intensity"], Json::array({1.0, 2.0, 3.0}));
    EXPECT_EQ(lights[0]["cone_angle"], 40.0);
    EXPECT_EQ(lights[0]["cone_delta"], 10.0);
    EXPECT_EQ(lights[1]["direction"], Json::array({0.0, 0.0, 1.0}));
    EXPECT_NEAR(lights[1]["intensity"][0].get<double>(), 10.0 / 0.715236, 1e-4);
    EXPECT_FALSE(hasWarning(c, "spot"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.lights.size(), 2u);
    ASSERT_TRUE(std::holds_alternative<SpotLight>(scene.lights[0]));
    EXPECT_NEAR(std::get<SpotLight>(scene.lights[0]).cosFalloffEnd, std::cos(40.0 * std::numbers::pi / 180.0),
                1e-6);
    EXPECT_THROW(
        convert(kCamera + "WorldBegin\nLightSource \"spot\" \"float coneangle\" 10 \"float conedelta\" 20\n"),
        InputError);
}

TEST(PbrtMapping, LightsAndEmission) {
    auto c =
        convert(kCamera +
                "WorldBegin\nTranslate 0 1 0\n"
                "LightSource \"point\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [1 0 0]\n"
                "LightSource \"point\" \"float power\" 100\n"
                "LightSource \"distant\" \"point3 from\" [0 1 0] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n"
                "LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
                "LightSource \"infinite\" \"rgb L\" [0.1 0.1 0.1]\n"
                "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 5 6] \"float scale\" 0.5 \"bool "
                "twosided\" true\n"
                "Shape \"sphere\"\nAttributeEnd\nShape \"sphere\"\n"
                "AreaLightSource \"diffuse\" \"blackbody L\" 3000\nShape \"sphere\"\n");
    const Json& lights = c.document["lights"];
    EXPECT_EQ(lights[0]["position"], Json::array({1.0, 1.0, 0.0}));
    EXPECT_EQ(lights[0]["intensity"], Json::array({2.0, 4.0, 6.0}));
    EXPECT_NEAR(lights[1]["intensity"][0].get<double>(), 100.0 / (4.0 * std::numbers::pi), 1e-5);
    EXPECT_EQ(lights[2]["type"], "directional");
    EXPECT_EQ(lights[2]["direction"], Json::array({0.0, -1.0, 0.0}));
    EXPECT_NEAR(c.document["background"][2].get<double>(), 0.4, 1e-6);
    const Json& shapes = c.document["shapes"];
    EXPECT_EQ(shapes[0]["emission"], Json::parse(R"({"radiance": [2.0, 2.5, 3.0], "two_sided": true})"));
    EXPECT_FALSE(shapes[1].contains("emission"));  // AttributeEnd ended the area light
    const Rgb blackbody = blackbodyRgb(3000.0);
    EXPECT_NEAR(shapes[2]["emission"]["radiance"][0].get<double>(), blackbody.r, 1e-5);
    EXPECT_FALSE(shapes[2]["emission"]["two_sided"].get<bool>());
}

TEST(PbrtMapping, ImageInfiniteLightsKeepPbrtsLatitudeLongitudeOrientation) {
    // pbrt's convention (pbrt-v3, and pbrt-v4's imgtool makeequiarea): column u = phi / 2 pi with
    // phi = atan2(y, x), row v = theta / pi from +z, in the light's space. Checked against the
    // same image read in penumbra's own convention, with the light turned so that its +z is world
    // +y, under a camera that needs no mirroring and under one that does (world x -> -x).
    const std::string sky =
        (fs::path(PENUMBRA_SOURCE_DIR) / "scenes" / "textures" / "sky.exr").string();  // 512 x 256
    const Scene plain =
        parseScene(R"({"environment": {"type": "image", "file": ")" + sky + R"("}})", "test.json");
    const std::string mirroredCamera = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n";
    for (const std::string& camera : {kCamera, mirroredCamera}) {
        const bool mirrored = camera == mirroredCamera;
        auto c = convert(
            camera +
            "WorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"" +
            sky + "\" \"float scale\" 2\nAttributeEnd\n");
        const Json& environment = c.document["environment"];
        EXPECT_EQ(environment["type"], "image");
        EXPECT_EQ(environment["scale"], 2.0);
        EXPECT_EQ(environment.value("mirror", false),
                  !mirrored);  // pbrt's map is mirrored in a right-handed world
        EXPECT_FALSE(c.document.contains("background"));
        const Scene scene = buildPbrtScene(c, "test.pbrt");
        for (int i = 0; i < 40; ++i) {
            const double s = (double((i * 97) % 512) + 0.5) / 512.0,
                         t = (double((i * 37) % 256) + 0.5) / 256.0;
            const double phi = 2.0 * std::numbers::pi * s, theta = std::numbers::pi * t;
            const Vec3f light{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                              float(std::cos(theta))};
            Vec3f world{light.x, light.z, -light.y};  // Rotate -90 about x
            if (mirrored) world.x = -world.x;
            const Vec3f own{float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
                            float(-std::sin(theta) * std::cos(phi))};
            const Rgb expected = plain.environment.radiance(own) * 2.0f,
                      found = scene.environment.radiance(world);
            EXPECT_NEAR(found.r, expected.r, 1e-5f * (1.0f + expected.r)) << s << " " << t;
            EXPECT_NEAR(found.b, expected.b, 1e-5f * (1.0f + expected.b)) << s << " " << t;
        }
    }
    EXPECT_THROW(convert(kCamera + "WorldBegin\nLightSource \"infinite\" \"string filename\" \"" + sky +
                         "\" \"rgb L\" [1 1 1]\n"),
                 InputError);
}

// pbrt-v4's EqualAreaSquareToSphere (util/math.cpp; Clarberg 2008), written out from its
// definition: the square [0, 1]^2 onto the sphere, the square's centre at +z.
Vec3f pbrtEqualAreaSquareToSphere(double s, double t) {
    const double u = 2.0 * s - 1.0, v = 2.0 * t - 1.0, up = std::abs(u), vp = std::abs(v);
    const double signedDistance = 1.0 - (up + vp), r = 1.0 - std::abs(signedDistance);
    const double phi = (r == 0.0 ? 1.0 : (vp - up) / r + 1.0) * std::numbers::pi / 4.0;
    const double z = std::copysign(1.0 - r * r, signedDistance);
    const double ring = r * std::sqrt(2.0 - r * r);
    return {float(std::copysign(std::cos(phi), u) * ring), float(std::copysign(std::sin(phi), v) * ring),
            float(z)};
}

TEST(PbrtMapping, SquareInfiniteLightsArePbrtV4sEqualAreaMaps) {
    // A square map whose every texel has its own colour; pbrt-v4 looks texel (s, t) up in the
    // light's direction pbrtEqualAreaSquareToSphere(s, t) (ImageInfiniteLight::ImageLe, rows from
    // the top). The light is turned so that its +z is world +y, under a camera that needs no
    // mirroring and under one that does (world x -> -x).
    const int size = 16;
    const fs::path map =
        fs::temp_directory_path() / ("penumbra-equal-area-" + std::to_string(::getpid()) + ".exr");
    {
        std::vector<Imf::Rgba> pixels;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) pixels.emplace_back(float(x + 1), float(y + 1), 0.5f);
        Imf::RgbaOutputFile out(map.c_str(), size, size, Imf::WRITE_RGB);
        out.setFrameBuffer(pixels.data(), 1, size);
        out.writePixels(size);
    }
    const std::string mirroredCamera = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n";
    for (const std::string& camera : {kCamera, mirroredCamera}) {
        const bool mirrored = camera == mirroredCamera;
        auto c = convert(
            camera +
            "WorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"" +
            map.string() + "\" \"float scale\" 2\nAttributeEnd\n");
        const Json& environment = c.document["environment"];
        EXPECT_EQ(environment["mapping"], "equal_area");
        EXPECT_EQ(environment.value("mirror", false), mirrored);
        const Scene scene = buildPbrtScene(c, "test.pbrt");
        int checked = 0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const Vec3f light = pbrtEqualAreaSquareToSphere((x + 0.5) / size, (y + 0.5) / size);
                Vec3f world{light.x, light.z, -light.y};  // Rotate -90 about x
                if (mirrored) world.x = -world.x;
                const Rgb found = scene.environment.radiance(world);
                EXPECT_EQ(found, Rgb(2.0f * float(x + 1), 2.0f * float(y + 1), 1.0f)) << x << " " << y;
                ++checked;
            }
        EXPECT_EQ(checked, size * size);
    }
    fs::remove(map);
}

TEST(PbrtMapping, GoniometricLightsLookTheirImageUpAsPbrtV4) {
    // pbrt-v4's GoniometricLight::I looks texel (s, t) up in the light-space direction
    // pbrtEqualAreaSquareToSphere(s, t) after its swap of y and z: world = R (x, z, y). Every
    // texel has its own value (the mean of its channels); the light is moved and turned about z.
    const int size = 16;
    const fs::path map =
        fs::temp_directory_path() / ("penumbra-goniometric-" + std::to_string(::getpid()) + ".exr");
    double sum = 0.0;
    {
        std::vector<Imf::Rgba> pixels;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const float value = float(y * size + x + 1);
                pixels.emplace_back(value - 0.5f, value, value + 0.5f);
                sum += value;
            }
        Imf::RgbaOutputFile out(map.c_str(), size, size, Imf::WRITE_RGB);
        out.setFrameBuffer(pixels.data(), 1, size);
        out.writePixels(size);
    }
    const std::string light =
        "WorldBegin\nAttributeBegin\nTranslate 1 2 3\nRotate 30 0 0 1\nLightSource \"goniometric\" "
        "\"string filename\" \"" +
        map.string() + "\" ";
    auto c = convert(kCamera + light + "\"float scale\" 2\nAttributeEnd\n");
    EXPECT_FALSE(hasWarning(c, "goniometric"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.lights.size(), 1u);
    const auto& goniometric = std::get<GoniometricLight>(scene.lights[0]);
    EXPECT_NEAR(goniometric.position.x, 1.0f, 1e-6f);
    EXPECT_NEAR(goniometric.position.y, 2.0f, 1e-6f);
    EXPECT_NEAR(goniometric.position.z, 3.0f, 1e-6f);
    const double c30 = std::cos(std::numbers::pi / 6.0), s30 = std::sin(std::numbers::pi / 6.0);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const Vec3f l = pbrtEqualAreaSquareToSphere((x + 0.5) / size, (y + 0.5) / size);
            const Vec3f swapped{l.x, l.z, l.y};
            const Vec3f world{float(c30 * swapped.x - s30 * swapped.y),
                              float(s30 * swapped.x + c30 * swapped.y), swapped.z};
            EXPECT_EQ(goniometric.intensity(world), Rgb(2.0f * float(y * size + x + 1))) << x << " " << y;
        }
    // The flux: 4 pi times the image's mean (each texel covers 4 pi / size^2), times the scale;
    // with "power", pbrt-v4 scales the light to that flux.
    const double flux = 4.0 * std::numbers::pi * sum / (size * size);
    EXPECT_NEAR(goniometric.power(1.0), 2.0 * flux, 1e-5 * flux);
    auto withPower = convert(kCamera + light + "\"float power\" 1000\nAttributeEnd\n");
    const Scene powered = buildPbrtScene(withPower, "test.pbrt");
    EXPECT_NEAR(std::get<GoniometricLight>(powered.lights.at(0)).power(1.0), 1000.0, 1e-3);
    // A non-square image is not an equal-area map.
    const fs::path wide = map.string() + "-wide.exr";
    {
        std::vector<Imf::Rgba> pixels(2 * size * size, Imf::Rgba(1.0f, 1.0f, 1.0f));
        Imf::RgbaOutputFile out(wide.c_str(), 2 * size, size, Imf::WRITE_RGB);
        out.setFrameBuffer(pixels.data(), 1, 2 * size);
        out.writePixels(size);
    }
    auto nonSquare = convert(kCamera + "WorldBegin\nLightSource \"goniometric\" \"string filename\" \"" +
                             wide.string() + "\"\n");
    EXPECT_THROW(buildPbrtScene(nonSquare, "test.pbrt"), InputError);
    fs::remove(map);
    fs::remove(wide);
}

TEST(PbrtMapping, TexturesBecomeTextureObjects) {
    const std::string floor = (fs::path(PENUMBRA_SOURCE_DIR) / "scenes" / "textures" / "floor.png").string();
    auto c =
        convert(kCamera +
                "WorldBegin\n"
                "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"" +
                floor +
                "\" \"string wrap\" \"clamp\" "
                "\"float uscale\" 4 \"float vscale\" 2 \"float udelta\" 0.5 \"string encoding\" \"linear\" "
                "\"string filter\" \"point\"\n"
                "Texture \"bright\" \"spectrum\" \"scale\" \"texture tex\" \"img\" \"float scale\" 2\n"
                "Texture \"check\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1] "
                "\"float uscale\" 8 \"float vscale\" 8\n"
                "Texture \"k\" \"float\" \"constant\" \"float value\" 0.36\n"
                "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"texture reflectance\" \"bright\"\n"
                "MakeNamedMaterial \"b\" \"string type\" \"coateddiffuse\" \"texture reflectance\" \"check\" "
                "\"texture roughness\" \"k\"\n"
                "MakeNamedMaterial \"c\" \"string type\" \"conductor\" \"texture reflectance\" \"img\"\n");
    const Json& m = c.document["materials"];
    // pbrt's st = (uscale u + udelta, vscale v + vdelta) is penumbra's (u, v) * uv_scale + uv_offset.
    Json image{
        {"type", "image"},         {"file", floor},          {"wrap", "clamp"},         {"filter", "closest"},
        {"color_space", "linear"}, {"uv_scale", {4.0, 2.0}}, {"uv_offset", {0.5, 0.0}}, {"scale", 2.0}};
    EXPECT_EQ(m["a"]["albedo"], image);
    EXPECT_EQ(
        m["b"]["albedo"],
        Json::parse(R"({"type": "checkerboard", "colors": [[1, 0, 0], [0, 0, 1]], "uv_scale": [8, 8]})"));
    EXPECT_NEAR(m["b"]["alpha"].get<double>(), 0.6, 1e-7);  // a constant float texture: sqrt(0.36)
    // A conductor's reflectance (pbrt-v4's artist-friendly conductor) takes the texture too.
    EXPECT_EQ(m["c"]["reflectance"]["type"], "image");
    EXPECT_FALSE(m["c"].contains("k"));
    EXPECT_FALSE(hasWarning(c, "a texture where penumbra takes none"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    const auto named = std::find(scene.materialNames.begin(), scene.materialNames.end(), "a");
    ASSERT_NE(named, scene.materialNames.end());
    EXPECT_TRUE(scene.materials[size_t(named - scene.materialNames.begin())].isTextured());
}

// pbrt-v4's 2D mappings of the point (TextureMapping2D::Create): spherical and cylindrical in the
// texture's space (the transform current at the Texture directive), which take no uscale or
// udelta; planar with its v1, v2 (defaults x, y) and udelta, vdelta. An alpha is looked up at
// (u, v): its mapping is dropped with a warning. An unknown mapping is an error at its line.
TEST(PbrtMapping, TextureMappingsOfThePoint) {
    auto c = convert(kCamera +
                     "WorldBegin\n"
                     "AttributeBegin\nTranslate 0 0 3\n"
                     "Texture \"globe\" \"spectrum\" \"checkerboard\" \"string mapping\" \"spherical\" "
                     "\"float uscale\" 4\n"
                     "AttributeEnd\n"
                     "Texture \"can\" \"float\" \"checkerboard\" \"string mapping\" \"cylindrical\"\n"
                     "Texture \"floor\" \"spectrum\" \"checkerboard\" \"string mapping\" \"planar\" "
                     "\"vector3 v1\" [0 0 1] \"float udelta\" 0.5\n"
                     "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"texture reflectance\" \"globe\"\n"
                     "MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"texture reflectance\" \"floor\"\n"
                     "Shape \"sphere\" \"texture alpha\" \"can\"\n");
    const Json& m = c.document["materials"];
    const Json& globe = m["a"]["albedo"];
    EXPECT_EQ(globe["mapping"]["type"], "spherical");
    EXPECT_EQ(globe["mapping"]["transform"][0]["matrix"][3], 0.0);
    EXPECT_EQ(globe["mapping"]["transform"][0]["matrix"][11], 3.0);  // the translation's z
    EXPECT_FALSE(globe.contains("uv_scale"));
    const Json& floor = m["b"]["albedo"];
    EXPECT_EQ(floor["mapping"], Json::parse(R"({"type": "planar", "v1": [0, 0, 1], "v2": [0, 1, 0]})"));
    EXPECT_EQ(floor["uv_offset"], Json::parse("[0.5, 0]"));
    EXPECT_FALSE(hasWarning(c, "mapping \"spherical\""));
    EXPECT_TRUE(hasWarning(c, "an alpha texture is looked up at the surface's (u, v)"));
    const Json& alpha = c.document["shapes"][0]["alpha"];
    EXPECT_EQ(alpha["type"], "checkerboard");
    EXPECT_FALSE(alpha.contains("mapping"));
    EXPECT_NO_THROW(buildPbrtScene(c, "test.pbrt"));

    const InputError e = testing::catchInputError([] {
        convert(kCamera +
                "WorldBegin\nTexture \"t\" \"float\" \"checkerboard\" \"string mapping\" \"conic\"\n");
    });
    EXPECT_CONTAINS(e.what(), "test.pbrt:");
    EXPECT_CONTAINS(e.what(),
                    "unknown texture mapping \"conic\" (expected uv, spherical, cylindrical or planar)");
}

// pbrt-v4's procedural and composite textures become penumbra's (textures/procedural_texture.h),
// inputs of inputs nested, the 3D ones placed by the transform current at their definition.
TEST(PbrtMapping, ProceduralAndCompositeTextures) {
    auto c =
        convert(kCamera +
                "WorldBegin\n"
                "AttributeBegin\nScale 2 2 2\n"
                "Texture \"noise\" \"float\" \"fbm\" \"integer octaves\" 5 \"float roughness\" 0.4\n"
                "Texture \"veins\" \"spectrum\" \"marble\" \"float scale\" 3 \"float variation\" 0.5\n"
                "Texture \"cube\" \"spectrum\" \"checkerboard\" \"integer dimension\" 3 "
                "\"rgb tex1\" [1 0 0] \"texture tex2\" \"veins\"\n"
                "Rotate 90 1 0 0\n"
                "Texture \"up\" \"spectrum\" \"directionmix\" \"rgb tex1\" [1 1 1] \"rgb tex2\" [0 0 0] "
                "\"vector3 dir\" [0 1 0]\n"
                "AttributeEnd\n"
                "Texture \"blend\" \"spectrum\" \"mix\" \"rgb tex1\" [0 0 1] \"texture tex2\" \"cube\" "
                "\"texture amount\" \"noise\"\n"
                "Texture \"spots\" \"spectrum\" \"dots\" \"rgb inside\" [1 0 0] \"float uscale\" 4 "
                "\"float vscale\" 4\n"
                "Texture \"ramp\" \"float\" \"bilerp\" \"float v11\" 0.5\n"
                "Texture \"waves\" \"float\" \"windy\"\n"
                "Texture \"skin\" \"float\" \"wrinkled\"\n"
                "Texture \"loud\" \"spectrum\" \"scale\" \"texture tex\" \"spots\" \"texture scale\" "
                "\"waves\"\n"
                "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"texture reflectance\" \"blend\"\n"
                "MakeNamedMaterial \"b\" \"string type\" \"diffuse\" \"texture reflectance\" \"up\"\n"
                "MakeNamedMaterial \"c\" \"string type\" \"diffuse\" \"texture reflectance\" \"loud\"\n"
                "MakeNamedMaterial \"d\" \"string type\" \"diffuse\" \"texture displacement\" \"skin\"\n"
                "MakeNamedMaterial \"e\" \"string type\" \"diffuse\" \"texture displacement\" \"ramp\"\n");
    EXPECT_FALSE(hasWarning(c, "not supported"));
    const Json& m = c.document["materials"];
    const Json& blend = m["a"]["albedo"];
    EXPECT_EQ(blend["type"], "mix");
    EXPECT_EQ(blend["textures"][0], Json::parse("[0.0, 0.0, 1.0]"));
    EXPECT_EQ(blend["textures"][1]["type"], "checkerboard_3d");
    EXPECT_EQ(blend["textures"][1]["colors"][1]["type"], "marble");
    EXPECT_EQ(blend["textures"][1]["colors"][1]["scale"], 3.0);
    EXPECT_EQ(blend["amount"]["type"], "fbm");
    EXPECT_EQ(blend["amount"]["octaves"], 5);
    // Defined under Scale 2: texture space is the world scaled by 2.
    EXPECT_EQ(blend["amount"]["transform"][0]["matrix"][0], 2.0);
    // The direction (0, 1, 0) turned by Rotate 90 about x: (0, 0, 1).
    const Json& up = m["b"]["albedo"];
    EXPECT_EQ(up["type"], "direction_mix");
    EXPECT_NEAR(up["direction"][2].get<double>(), 1.0, 1e-12);
    EXPECT_NEAR(up["direction"][1].get<double>(), 0.0, 1e-12);
    const Json& loud = m["c"]["albedo"];
    EXPECT_EQ(loud["type"], "scale");
    EXPECT_EQ(loud["texture"]["type"], "dots");
    EXPECT_EQ(loud["texture"]["uv_scale"], Json::parse("[4.0, 4.0]"));
    EXPECT_EQ(loud["scale"]["type"], "windy");
    EXPECT_EQ(m["d"]["bump"]["type"], "wrinkled");
    EXPECT_EQ(m["e"]["bump"], Json::parse(R"({"type": "bilerp", "values": [0.0, 0.0, 1.0, 0.5]})"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    for (const char* name : {"a", "b", "c"}) {
        const auto named = std::find(scene.materialNames.begin(), scene.materialNames.end(), name);
        ASSERT_NE(named, scene.materialNames.end());
        EXPECT_TRUE(scene.materials[size_t(named - scene.materialNames.begin())].isTextured()) << name;
    }
}

// A textured roughness goes to penumbra as the texture, with pbrt-v4's alpha = sqrt(r) (or r under
// remaproughness false); uroughness and vroughness of two textures, or of a texture and a number,
// as one per axis; a conductor's eta and k textures as themselves.
TEST(PbrtMapping, TexturedRoughness) {
    auto c = convert(
        kCamera +
        "WorldBegin\n"
        "Texture \"r\" \"float\" \"checkerboard\" \"float tex1\" 0.04 \"float tex2\" 0.36\n"
        "Texture \"s\" \"float\" \"fbm\"\n"
        "Texture \"e\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [0.2 0.3 0.4] \"rgb tex2\" [1 1 1]\n"
        "MakeNamedMaterial \"metal\" \"string type\" \"conductor\" \"texture roughness\" \"r\"\n"
        "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"texture uroughness\" \"s\" "
        "\"texture vroughness\" \"s\" \"bool remaproughness\" false\n"
        "MakeNamedMaterial \"paint\" \"string type\" \"coateddiffuse\" \"texture roughness\" \"r\"\n"
        "MakeNamedMaterial \"brushed\" \"string type\" \"conductor\" \"texture uroughness\" \"r\" "
        "\"texture vroughness\" \"s\"\n"
        "MakeNamedMaterial \"combed\" \"string type\" \"conductor\" \"texture uroughness\" \"r\" "
        "\"float vroughness\" 0.25 \"texture eta\" \"e\" \"texture k\" \"e\"\n");
    const Json& m = c.document["materials"];
    EXPECT_EQ(m["metal"]["type"], "rough_conductor");
    EXPECT_EQ(m["metal"]["roughness"]["type"], "checkerboard");
    EXPECT_EQ(m["metal"]["roughness_mapping"], "sqrt");
    EXPECT_EQ(m["glass"]["type"], "rough_dielectric");
    EXPECT_EQ(m["glass"]["roughness"]["type"], "fbm");
    EXPECT_EQ(m["glass"]["roughness_mapping"], "identity");
    EXPECT_EQ(m["paint"]["roughness"]["type"], "checkerboard");
    EXPECT_EQ(m["brushed"]["roughness"][0]["type"], "checkerboard");
    EXPECT_EQ(m["brushed"]["roughness"][1]["type"], "fbm");
    EXPECT_EQ(m["combed"]["roughness"][1], 0.25);
    EXPECT_EQ(m["combed"]["eta"]["type"], "checkerboard");
    EXPECT_EQ(m["combed"]["k"]["type"], "checkerboard");
    EXPECT_FALSE(hasWarning(c, "a texture where penumbra takes none"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    auto material = [&](const std::string& name) -> const Material& {
        const auto named = std::find(scene.materialNames.begin(), scene.materialNames.end(), name);
        EXPECT_NE(named, scene.materialNames.end()) << name;
        return scene.materials[size_t(named - scene.materialNames.begin())];
    };
    TextureQuery odd;
    odd.uv = {1.5f, 0.5f};
    EXPECT_FLOAT_EQ(std::get<RoughConductor>(material("metal").at(odd).model()).distribution.alphaX, 0.6f);
    const RoughConductor combed = std::get<RoughConductor>(material("combed").at(odd).model());
    EXPECT_FLOAT_EQ(combed.distribution.alphaX, 0.6f);  // sqrt(0.36)
    EXPECT_FLOAT_EQ(combed.distribution.alphaY, 0.5f);  // sqrt(0.25)
    EXPECT_FLOAT_EQ(combed.eta.r, 1.0f);
    TextureQuery even;
    even.uv = {0.5f, 0.5f};
    const RoughConductor combedEven = std::get<RoughConductor>(material("combed").at(even).model());
    EXPECT_FLOAT_EQ(combedEven.eta.g, 0.3f);
    EXPECT_FLOAT_EQ(combedEven.k.b, 0.4f);
}

// pbrt-v4's named glasses (F5, F10, F11 are Schott's SF5, SF10, SF11: n_d of their data sheets),
// and spectrum files (.spd): a conductor of gold given by two files of our own, read once, and
// every malformed file refused at its line.
TEST(PbrtSpectrum, NamedGlassesAndSpectrumFiles) {
    const std::string folder = ::testing::TempDir() + "/penumbra-spd";
    std::filesystem::create_directories(folder + "/spds");
    // Constant spectra: as an index or a reflectance, a constant spectrum c is exactly c.
    std::ofstream(folder + "/spds/Au.eta.spd")
        << "# eta of a grey metal\n400 0.25\n550 0.25 # green\n700 0.25\n";
    std::ofstream(folder + "/spds/Au.k.spd") << "  380\t3.5 780 3.5\n";
    std::ofstream(folder + "/spds/odd.spd") << "400 1\n500\n";
    std::ofstream(folder + "/spds/down.spd") << "400 1\n# second line\n300 1\n";
    std::ofstream(folder + "/spds/word.spd") << "400 1 500 x\n";
    const auto convertIn = [&](const std::string& text) {
        return convertPbrtText(kCamera + "WorldBegin\n" + text + "Shape \"sphere\"\n",
                               folder + "/scene.pbrt");
    };
    const PbrtConversion c = convertIn(
        "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"spds/Au.eta.spd\" "
        "\"spectrum k\" \"spds/Au.k.spd\"\n"
        "MakeNamedMaterial \"again\" \"string type\" \"conductor\" \"spectrum eta\" \"spds/Au.eta.spd\"\n"
        "MakeNamedMaterial \"flint\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-F11\"\n"
        "MakeNamedMaterial \"f10\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-F10\"\n"
        "MakeNamedMaterial \"f5\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-F5\"\n");
    const Json& m = c.document["materials"];
    for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(m["gold"]["eta"][ch].get<double>(), 0.25, 1e-6);
        EXPECT_NEAR(m["gold"]["k"][ch].get<double>(), 3.5, 1e-5);
    }
    EXPECT_NEAR(m["flint"]["eta"].get<double>(), 1.78472, 1e-5);
    EXPECT_NEAR(m["f10"]["eta"].get<double>(), 1.72825, 1e-5);
    EXPECT_NEAR(m["f5"]["eta"].get<double>(), 1.67270, 1e-5);
    const std::vector<std::filesystem::path> read(c.files.begin(), c.files.end());
    EXPECT_EQ(std::count(read.begin(), read.end(), std::filesystem::path(folder + "/spds/Au.eta.spd")), 1);

    const auto errorOf = [&](const std::string& file) {
        return std::string(testing::catchInputError([&] {
                               convertIn("Material \"conductor\" \"spectrum eta\" \"spds/" + file + "\"\n");
                           }).what());
    };
    EXPECT_CONTAINS(errorOf("odd.spd"),
                    "odd.spd:2: a spectrum file holds (wavelength, value) pairs: this one holds 3");
    EXPECT_CONTAINS(errorOf("down.spd"), "down.spd:3: wavelengths must increase: 300 follows 400");
    EXPECT_CONTAINS(errorOf("word.spd"), "word.spd:1: expected a number, found 'x'");
    EXPECT_CONTAINS(errorOf("missing.spd"), "scene.pbrt:5:");
    EXPECT_CONTAINS(errorOf("missing.spd"), "is neither a named spectrum");
}

TEST(PbrtSpectrum, BlackbodiesHaveUnitLuminanceAndTheirColour) {
    for (double t : {1500.0, 3000.0, 6504.0, 10000.0})
        EXPECT_NEAR(blackbodyRgb(t).luminance(), 1.0, 2e-3) << t;
    const Rgb warm = blackbodyRgb(2000.0), daylight = blackbodyRgb(6504.0), blue = blackbodyRgb(12000.0);
    EXPECT_GT(warm.r, warm.g);
    EXPECT_GT(warm.g, warm.b);
    EXPECT_GT(blue.b, blue.r);
    // 6504 K is close to D65, sRGB's white (not exactly: D65 is not a blackbody).
    EXPECT_NEAR(daylight.r / daylight.b, 1.0, 0.08);
    // A constant reflectance spectrum is that grey.
    const Rgb grey = reflectanceSpectrumRgb({300, 0.4, 800, 0.4});
    EXPECT_NEAR(grey.r, 0.4, 1e-4);
    EXPECT_NEAR(grey.b, 0.4, 1e-4);
    EXPECT_FALSE(namedSpectrumRgb("metal-Unobtainium-eta"));
}

TEST(PbrtMapping, ShapesOfEveryKind) {
    const fs::path ply = fs::path(PENUMBRA_TEST_DATA_DIR) / "scenes" / "meshes" / "square_ascii.ply";
    auto c = convert(kCamera +
                     "WorldBegin\nShape \"sphere\" \"float radius\" 2\nShape \"disk\" \"float radius\" 3\n"
                     "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n"
                     "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"point2 uv\" [0 0 1 0 0 1]\n"
                     "Shape \"plymesh\" \"string filename\" \"" +
                     ply.string() +
                     "\"\n"
                     "Shape \"curve\" \"point3 P\" [0 0 0 1 1 1 2 2 2 3 3 3]\n"
                     "Shape \"hyperboloid\" \"point3 p1\" [0 0 0]\n");
    const Json& s = c.document["shapes"];
    ASSERT_EQ(s.size(), 6u);
    EXPECT_EQ(s[0]["radius"], 2.0);
    EXPECT_EQ(s[1]["type"], "disk");
    // A bilinear patch is penumbra's own shape, its corners in pbrt-v4's order.
    EXPECT_EQ(s[2]["type"], "bilinear_mesh");
    EXPECT_EQ(s[2]["indices"], Json::array({0, 1, 2, 3}));
    EXPECT_EQ(s[3]["uvs"][1], Json::array({1.0, 0.0}));
    EXPECT_EQ(s[4]["type"], "mesh_file");
    EXPECT_EQ(s[5]["type"], "curves");
    // pbrt-v3's quadrics, which pbrt-v4 dropped.
    EXPECT_TRUE(hasWarning(c, "Shape \"hyperboloid\" is not supported and was left out"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    EXPECT_EQ(scene.meshes.size(), 3u);
    EXPECT_EQ(scene.patches.size(), 1u);
    EXPECT_EQ(scene.curves.size(), 1u);
    EXPECT_EQ(scene.spheres.size(), 1u);
    EXPECT_EQ(scene.meshFiles.size(), 1u);
}

// A bilinearmesh is penumbra's bilinear_mesh with its normals, uvs and orientation, placed by its
// transform; one that emits (or moves, or has a cut-out) is two triangles a patch, with a warning
// only when a patch is not flat (its triangles then are not the same surface); an object's patches are
// placed as copies.
TEST(PbrtMapping, BilinearPatches) {
    auto c = convert(
        kCamera +
        "WorldBegin\nAttributeBegin\nTranslate 0 0 5\nReverseOrientation\n"
        "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 1 0 1 1 1 1 0] \"point2 uv\" [0 0 2 0 0 2 2 2]\n"
        "AttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
        "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n"
        "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 1 0 1 1 1 1 0]\n"
        "AttributeEnd\n"
        "ObjectBegin \"tile\"\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 1 0 1 1 1 1 0]\nObjectEnd\n"
        "ObjectInstance \"tile\"\n");
    const Json& s = c.document["shapes"];
    ASSERT_EQ(s.size(), 4u);
    EXPECT_EQ(s[0]["type"], "bilinear_mesh");
    EXPECT_EQ(s[0]["indices"], Json::array({0, 1, 2, 3}));
    EXPECT_EQ(s[0]["uvs"][3], Json::array({2.0, 2.0}));
    EXPECT_EQ(s[0]["reverse_orientation"], true);
    EXPECT_TRUE(s[0].contains("transform"));
    // The emitters: a flat patch without a warning, a curved one with.
    EXPECT_EQ(s[1]["type"], "triangle_mesh");
    EXPECT_TRUE(s[1].contains("emission"));
    EXPECT_EQ(s[2]["type"], "triangle_mesh");
    EXPECT_EQ(std::count_if(c.warnings.begin(), c.warnings.end(),
                            [](const std::string& w) {
                                return w.find("rendered as two triangles each") != std::string::npos;
                            }),
              1);
    EXPECT_EQ(s[3]["type"], "bilinear_mesh");
    EXPECT_TRUE(hasWarning(c, "object instances of bilinear patches"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.patches.size(), 2u);
    EXPECT_TRUE(scene.patches[0].reversed);
    EXPECT_NEAR(scene.patches[0].positions[1].z, 6.0f, 1e-6f);
    EXPECT_EQ(scene.meshes.size(), 2u);
}

TEST(PbrtMapping, FilmSamplerFilterIntegrator) {
    auto c = convert(
        "Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 32 \"float cropwindow\" [0 0.5 0 "
        "1]\n"
        "Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 5\n"
        "PixelFilter \"gaussian\"\nIntegrator \"volpath\" \"integer maxdepth\" 9 \"bool regularize\" true\n"
        "WorldBegin\n");
    EXPECT_EQ(c.document["film"]["resolution"], Json::array({64, 32}));
    EXPECT_EQ(c.document["film"]["spp"], 15);
    EXPECT_EQ(c.document["film"]["filter"]["type"], "tent");
    EXPECT_NEAR(c.document["film"]["filter"]["radius"].get<double>(), 0.5 * std::sqrt(6.0), 1e-12);
    EXPECT_EQ(c.document["integrator"]["max_depth"], 9);
    EXPECT_EQ(c.document["film"]["crop_window"], Json::array({0.0, 0.5, 0.0, 1.0}));
    EXPECT_FALSE(hasWarning(c, "cropwindow"));
    EXPECT_TRUE(hasWarning(c, "regularize"));
    auto box =
        convert("PixelFilter \"box\"\nSampler \"independent\" \"integer pixelsamples\" 7\nWorldBegin\n");
    EXPECT_EQ(box.document["film"]["filter"], Json::parse(R"({"type": "box", "radius": 0.5})"));
    EXPECT_EQ(box.document["render"]["sampler"], "independent");
    EXPECT_EQ(box.document["film"]["spp"], 7);
}

// pbrt-v4's "lightsampler": "power" is ours, "bvh" our default (the key left out); "uniform"
// warns and keeps the default.
TEST(PbrtMapping, IntegratorLightSampler) {
    auto power = convert("Integrator \"path\" \"string lightsampler\" \"power\"\nWorldBegin\n");
    EXPECT_EQ(power.document["integrator"]["light_sampler"], "power");
    EXPECT_FALSE(hasWarning(power, "lightsampler"));
    auto bvh = convert("Integrator \"path\" \"string lightsampler\" \"bvh\"\nWorldBegin\n");
    EXPECT_FALSE(bvh.document["integrator"].contains("light_sampler"));
    EXPECT_FALSE(hasWarning(bvh, "lightsampler"));
    auto uniform = convert("Integrator \"path\" \"string lightsampler\" \"uniform\"\nWorldBegin\n");
    EXPECT_FALSE(uniform.document["integrator"].contains("light_sampler"));
    EXPECT_TRUE(hasWarning(uniform, "lightsampler"));
}

TEST(PbrtMapping, UnsupportedDirectivesWarnOnceWithACount) {
    auto c = convert(
        "WorldBegin\nAttribute \"shape\" \"float radius\" 2\n"
        "Attribute \"shape\" \"float radius\" 3\nShape \"sphere\" \"float nonsense\" 1\n");
    int attribute = 0;
    for (const std::string& w : c.warnings)
        if (w.find("Attribute is not supported") != std::string::npos) {
            ++attribute;
            EXPECT_NE(w.find("test.pbrt:2:1: "), std::string::npos) << w;
            EXPECT_NE(w.find("(2 times)"), std::string::npos) << w;
        }
    EXPECT_EQ(attribute, 1);
    EXPECT_TRUE(
        hasWarning(c, "test.pbrt:4:16: parameter \"float nonsense\" of Shape \"sphere\" is not supported"));
}

// Participating media: MakeNamedMedium with pbrt-v4's defaults (media.cpp: sigma_a and sigma_s 1),
// MediumInterface on the shapes after it where inside and outside differ, the camera's medium
// (the outside one at Camera), and a name never defined refused where it is used.
TEST(PbrtMapping, MediaBoundariesAndTheCameraMedium) {
    auto c = convert(
        "MediumInterface \"\" \"fog\"\n" + kCamera +
        "WorldBegin\n"
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_s\" [0.1 0.2 0.3] \"float g\" "
        "0.5\n"
        "MakeNamedMedium \"plain\" \"string type\" \"homogeneous\" \"float scale\" 2\n"
        "MakeNamedMedium \"ramp\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [0 1] "
        "\"point3 p1\" [2 1 1]\n"
        "Shape \"sphere\"\n"
        "AttributeBegin\nMediumInterface \"plain\" \"fog\"\nMaterial \"interface\"\nShape "
        "\"sphere\"\nAttributeEnd\n"
        "AttributeBegin\nMediumInterface \"fog\"\nShape \"sphere\"\nAttributeEnd\n");
    const Json& media = c.document["media"];
    EXPECT_EQ(media["fog"],
              Json::parse(
                  R"({"type": "homogeneous", "sigma_a": [1, 1, 1], "sigma_s": [0.1, 0.2, 0.3], "g": 0.5})"));
    EXPECT_EQ(media["plain"]["scale"], 2.0);
    EXPECT_EQ(media["ramp"]["type"], "grid");
    EXPECT_EQ(media["ramp"]["density"], Json::parse(R"({"resolution": [2, 1, 1], "values": [0, 1]})"));
    EXPECT_EQ(media["ramp"]["bounds"], Json::parse("[[0, 0, 0], [2, 1, 1]]"));
    EXPECT_EQ(c.document["camera"]["medium"], "fog");
    const Json& shapes = c.document["shapes"];
    // The MediumInterface before the camera holds in the world too (pbrt-v4's WorldBegin keeps it).
    EXPECT_EQ(shapes[0]["inside"], "");
    EXPECT_EQ(shapes[0]["outside"], "fog");
    EXPECT_EQ(shapes[1]["inside"], "plain");
    EXPECT_EQ(shapes[1]["outside"], "fog");
    EXPECT_FALSE(shapes[2].contains("inside"));  // the same medium on both sides: no boundary
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.media.size(), 3u);
    EXPECT_TRUE(scene.hasMedia());
    EXPECT_EQ(scene.spheres[1].media.inside, 1u);
    EXPECT_EQ(scene.spheres[1].media.outside, 0u);
    EXPECT_TRUE(scene.materials[scene.spheres[1].material].isInterface());

    const InputError e = testing::catchInputError(
        [] { convert("WorldBegin\nMediumInterface \"smoke\" \"\"\nShape \"sphere\"\n"); });
    EXPECT_EQ(e.where().line, 2);
    EXPECT_CONTAINS(e.message(), "medium \"smoke\" is not defined");
}

// pbrt-v4's nanovdb medium: the file's "density" grid, placed by the current transform; the file
// is the fixture the NanoVDB library wrote (tests/data/nanovdb).
TEST(PbrtMapping, NanoVdbMediaReadTheirFile) {
    const std::string file = (fs::path(PENUMBRA_TEST_DATA_DIR) / "nanovdb" / "smoke.nvdb").string();
    auto c = convert(
        "WorldBegin\nTranslate 0 1 0\nMakeNamedMedium \"smoke\" \"string type\" \"nanovdb\" "
        "\"string filename\" \"" +
        file + "\" \"float scale\" 4\n");
    const Json& smoke = c.document["media"]["smoke"];
    EXPECT_EQ(smoke["type"], "grid");
    EXPECT_EQ(smoke["density"], Json({{"file", file}, {"grid", "density"}}));
    EXPECT_EQ(smoke["scale"], 4.0);
    ASSERT_TRUE(smoke.contains("transform"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    const auto& grid = std::get<GridMedium>(scene.media.at(0));
    EXPECT_EQ(grid.density.nx * grid.density.ny * grid.density.nz, int(grid.density.values.size()));
    EXPECT_FLOAT_EQ(grid.toWorld.applyPoint({0, 0, 0}).y, 1.0f);
    EXPECT_FLOAT_EQ(grid.sigmaS.r, 4.0f);  // pbrt-v4's default sigma_s 1, times the scale
    // The file has a "temperature" grid too: pbrt-v4 makes the medium glow as its blackbody.
    EXPECT_EQ(smoke["temperature"], Json({{"file", file}, {"grid", "temperature"}}));
    ASSERT_TRUE(grid.emission.temperature.has_value());
    EXPECT_TRUE(grid.emission.emits());

    const InputError e = testing::catchInputError([] {
        convert(
            "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" "
            "\"none.nvdb\"\n");
    });
    EXPECT_CONTAINS(e.message(), "none.nvdb");
}

// Emitting grids and the procedural cloud: uniformgrid's temperature lattice with its offset and scale (and,
// without "Lescale", pbrt-v4's one-cell lattice of 1), its "Le" with a "Lescale" lattice, and rgbgrid's
// lattices (sigma_s 1 where not given, as pbrt-v4), cloud's parameters.
TEST(PbrtMapping, EmittingRgbGridAndCloudMedia) {
    auto c = convert(
        "WorldBegin\n"
        "MakeNamedMedium \"fire\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [1 2] "
        "\"float temperature\" [900 1500] \"float temperaturecutoff\" 100 \"float temperaturescale\" 2\n"
        "MakeNamedMedium \"lamp\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" [1 1] "
        "\"rgb Le\" [1 0.5 0.25] \"float Lescale\" [0 3]\n"
        "MakeNamedMedium \"tinted\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"rgb sigma_a\" [1 2 3 4 5 "
        "6] "
        "\"rgb Le\" [0 0 0 7 8 9] \"float Lescale\" 0.5 \"float scale\" 2 \"point3 p1\" [2 1 1]\n"
        "MakeNamedMedium \"puff\" \"string type\" \"cloud\" \"float density\" 2 \"float wispiness\" 0.5 "
        "\"float frequency\" 3 \"rgb sigma_s\" [10 10 10]\n");
    const Json& media = c.document["media"];
    const Json& fire = media["fire"];
    EXPECT_EQ(fire["temperature"], Json::parse(R"({"resolution": [2, 1, 1], "values": [900, 1500]})"));
    EXPECT_EQ(fire["temperature_offset"], 100.0);
    EXPECT_EQ(fire["temperature_scale"], 2.0);
    EXPECT_EQ(fire["emission_scale"], Json::parse(R"({"resolution": [1, 1, 1], "values": [1]})"));
    const Json& lamp = media["lamp"];
    EXPECT_EQ(lamp["emission"], Json::parse("[1, 0.5, 0.25]"));
    EXPECT_EQ(lamp["emission_scale"], Json::parse(R"({"resolution": [2, 1, 1], "values": [0, 3]})"));
    const Json& tinted = media["tinted"];
    EXPECT_EQ(tinted["type"], "rgb_grid");
    EXPECT_EQ(tinted["sigma_a"], Json::parse(R"({"values": [1, 2, 3, 4, 5, 6]})"));
    EXPECT_EQ(tinted["sigma_s"], Json::parse("[1, 1, 1]"));
    EXPECT_EQ(tinted["emission_scale"], 0.5);

    Json puff = media["puff"];
    puff.erase("transform");  // the world's: pbrt-v4's handedness flip
    EXPECT_EQ(puff, Json::parse(R"({"type": "cloud", "sigma_a": [1, 1, 1], "sigma_s": [10, 10, 10],
        "density": 2, "wispiness": 0.5, "frequency": 3, "bounds": [[0, 0, 0], [1, 1, 1]]})"));

    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.media.size(), 4u);
    EXPECT_FLOAT_EQ(std::get<CloudMedium>(scene.media[3]).frequency, 3.0f);
    // The fire at its hotter cell's centre, x = 0.75: (1500 - 100) * 2 = 2800 K, times the one-cell
    // lattice there, which is 1 at the box's centre and blends to 0 one cell (the box's width)
    // beyond it: 1 - 0.25 = 0.75.
    const GridMedium& fireGrid = std::get<GridMedium>(scene.media[0]);
    const Rgb atHotCell = fireGrid.emission.at({0.75f, 0.5f, 0.5f});
    const Rgb blackbody = blackbodyPeakNormalizedRgb(2800.0);
    for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(atHotCell[ch], 0.75f * blackbody[ch], 2e-4f * blackbody.maxComponent());
    const RgbGridMedium& tintedGrid = std::get<RgbGridMedium>(scene.media[2]);
    const Vec3f second{1.5f, 0.5f, 0.5f};                             // the second cell's centre
    EXPECT_EQ(tintedGrid.sigmaAAt(second), Rgb(8.0f, 10.0f, 12.0f));  // times scale 2
    EXPECT_EQ(tintedGrid.sigmaSAt(second), Rgb(2.0f));
    EXPECT_EQ(tintedGrid.emissionAt(second), Rgb(3.5f, 4.0f, 4.5f));  // times Lescale 0.5

    const InputError both = testing::catchInputError([] {
        convert(
            "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1] "
            "\"float temperature\" [1000] \"rgb Le\" [1 1 1]\n");
    });
    EXPECT_EQ(both.where().line, 2);
    EXPECT_CONTAINS(both.message(), "either \"Le\" or \"temperature\"");
    const InputError count = testing::catchInputError([] {
        convert(
            "WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2 "
            "\"rgb sigma_s\" [1 1 1]\n");
    });
    EXPECT_CONTAINS(count.message(),
                    "1 values for \"sigma_s\"; nx * ny * nz = 2 x 1 x 1 = 2 colours expected");
}

// A killeroo's shape: pbrt-v4's loopsubdiv, here a cube's control mesh of 12 triangles, refined
// at load into 12 * 4^levels triangles on the limit surface (inside the control cube, rounded),
// facing outward as the control mesh's winding does, inward under ReverseOrientation.
TEST(PbrtMapping, LoopSubdivisionSurfacesAreRefinedAtLoad) {
    const std::string cube =
        "Shape \"loopsubdiv\" \"integer levels\" 2 \"point3 P\" [-1 -1 -1 1 -1 -1 -1 1 -1 1 1 -1 -1 -1 1 1 "
        "-1 1 "
        "-1 1 1 1 1 1] \"integer indices\" [0 2 3 0 3 1 4 5 7 4 7 6 0 1 5 0 5 4 2 6 7 2 7 3 0 4 6 0 6 2 1 3 "
        "7 "
        "1 7 5]\n";
    for (const bool reverse : {false, true}) {
        const fs::path dir = fs::temp_directory_path() / "penumbra_pbrt_loopsubdiv_test";
        fs::create_directories(dir);
        std::ofstream(dir / "scene.pbrt") << kCamera << "WorldBegin\n"
                                          << (reverse ? "ReverseOrientation\n" : "") << cube;
        const PbrtConversion c = convertPbrtFile(dir / "scene.pbrt");
        EXPECT_EQ(c.document["shapes"][0]["subdivision"], (Json{{"scheme", "loop"}, {"levels", 2}}));
        EXPECT_FALSE(hasWarning(c, "left out"));
        std::vector<std::string> warnings;
        const Scene scene = loadSceneFile(dir / "scene.pbrt", {{}, &warnings});
        fs::remove_all(dir);
        ASSERT_EQ(scene.meshes.size(), 1u);
        const TriangleMesh& mesh = scene.meshes[0];
        ASSERT_EQ(mesh.triangleCount(), 12u * 16u);
        ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
        float nearest = 2.0f, outermost = 0.0f;
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3f p = mesh.positions[i];
            nearest = std::min(nearest, length(p));
            outermost = std::max({outermost, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
            const float side = dot(mesh.normals[i], normalize(p));
            EXPECT_GT(reverse ? -side : side, 0.5f) << i;
        }
        // Rounded, inside the control cube: measured 0.858 from the centre at the nearest, 0.870 at
        // the outermost coordinate (the control cube's faces are at 1, its corners at 1.73).
        EXPECT_GT(nearest, 0.8f);
        EXPECT_LT(outermost, 0.9f);
    }
    const InputError levels = testing::catchInputError([&] {
        convert(
            "WorldBegin\nShape \"loopsubdiv\" \"integer levels\" -1 \"point3 P\" [0 0 0 1 0 0 0 1 0] "
            "\"integer indices\" [0 1 2]\n");
    });
    EXPECT_CONTAINS(levels.what(), "test.pbrt:2");
    EXPECT_CONTAINS(levels.message(), "\"levels\" must be from 0 to 16, found -1");
}

// pbrt-v4's cylinder and partial disks: the same surfaces, phi swept counter-clockwise about +z from
// +x in the shape's space whichever side faces front.
TEST(PbrtMapping, CylindersAndPartialDisks) {
    auto c = convert(kCamera +
                     "WorldBegin\nShape \"cylinder\" \"float radius\" 2 \"float zmin\" 1 \"float zmax\" -0.5 "
                     "\"float phimax\" 270\nReverseOrientation\nShape \"disk\" \"float innerradius\" 0.5 "
                     "\"float phimax\" 90 \"float height\" 3\n");
    EXPECT_FALSE(hasWarning(c, "left out"));
    const Json& cylinder = c.document["shapes"][0];
    EXPECT_EQ(cylinder["type"], "cylinder");
    EXPECT_EQ(cylinder["base"], Json::array({0.0, 0.0, -0.5}));
    EXPECT_EQ(cylinder["axis"], Json::array({0.0, 0.0, 1.5}));
    EXPECT_EQ(cylinder["radius"], 2.0);
    EXPECT_EQ(cylinder["phi_max"], 270.0);
    EXPECT_FALSE(cylinder.contains("front"));  // outside
    const Json& disk = c.document["shapes"][1];
    EXPECT_EQ(disk["normal"], Json::array({0.0, 0.0, -1.0}));
    EXPECT_EQ(disk["inner_radius"], 0.5);
    // Facing -z, the sweep starts at pbrt-v4's phimax (90 degrees: +y) and ends at +x.
    EXPECT_NEAR(disk["start_direction"][0].get<double>(), 0.0, 1e-15);
    EXPECT_EQ(disk["start_direction"][1], 1.0);
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.meshes.size(), 2u);
    for (const Vec3f& p : scene.meshes[1].positions) {  // the quarter annulus in x >= 0, y >= 0
        EXPECT_GE(p.x, -1e-6f);
        EXPECT_GE(p.y, -1e-6f);
    }
    const InputError e = testing::catchInputError(
        [] { convert("WorldBegin\nShape \"cylinder\" \"float zmin\" 1 \"float zmax\" 1\n"); });
    EXPECT_CONTAINS(e.what(), "cylinder: zmin and zmax are equal");
}

// Partial spheres and ellipsoids, which pbrt-v4 scenes use (disney-cloud's medium boundary is a
// scaled sphere), load as triangles: the keys as pbrt-v4 clamps and orders them.
TEST(PbrtMapping, PartialSpheresAndEllipsoids) {
    auto c = convert(kCamera +
                     "WorldBegin\nShape \"sphere\" \"float radius\" 2 \"float zmin\" 3 \"float zmax\" -1 "
                     "\"float phimax\" 400\nScale 1 2 1\nShape \"sphere\"\n");
    const Json& partial = c.document["shapes"][0];
    EXPECT_EQ(partial["z_min"], -1.0);
    EXPECT_FALSE(partial.contains("z_max"));  // clamped to the radius: the top is whole
    EXPECT_FALSE(partial.contains("phi_max"));
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    EXPECT_EQ(scene.spheres.size(), 0u);
    EXPECT_EQ(scene.meshes.size(), 2u);
    const InputError e =
        testing::catchInputError([] { convert("WorldBegin\nShape \"sphere\" \"float phimax\" 0\n"); });
    EXPECT_CONTAINS(e.what(), "sphere: zmin, zmax and phimax leave nothing of it");
}

// pbrt-v4's displacement (a float texture of heights) and normalmap (a linear image) on a material:
// the bump and normal maps of penumbra's material (materials/normal_perturbation.h).
TEST(PbrtMapping, DisplacementAndNormalMapsPerturbTheShadingNormal) {
    auto c = convert(
        "WorldBegin\nTexture \"h\" \"float\" \"checkerboard\" \"float tex1\" 0 \"float tex2\" 0.01\n"
        "MakeNamedMaterial \"bumped\" \"string type\" \"diffuse\" \"texture displacement\" \"h\"\n"
        "MakeNamedMaterial \"mapped\" \"string type\" \"conductor\" \"string normalmap\" \"normals.png\"\n");
    EXPECT_FALSE(hasWarning(c, "displacement"));
    EXPECT_FALSE(hasWarning(c, "normalmap"));
    const Json& bump = c.document["materials"]["bumped"]["bump"];
    EXPECT_EQ(bump["type"], "checkerboard");
    EXPECT_EQ(
        c.document["materials"]["mapped"]["normal_map"],
        Json::parse(
            R"({"type": "image", "file": "normals.png", "color_space": "linear", "filter": "bilinear"})"));
}

// A shape's alpha: a float below 1 or a float texture, as the shape's cut-out (both backends test
// it, geometry/cut_out.h); 1 or more leaves the shape opaque; an object's shapes carry theirs into
// the prototype.
TEST(PbrtMapping, ShapeAlphaIsACutOut) {
    auto c =
        convert(kCamera +
                "WorldBegin\nTexture \"leaf\" \"float\" \"checkerboard\" \"float tex1\" 1 \"float tex2\" 0\n"
                "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2] \"float "
                "alpha\" 0.25\n"
                "Shape \"sphere\" \"texture alpha\" \"leaf\"\n"
                "Shape \"disk\" \"float alpha\" 1\n"
                "Shape \"disk\" \"float alpha\" -2\n"
                "ObjectBegin \"plant\"\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer "
                "indices\" [0 1 2] "
                "\"texture alpha\" \"leaf\"\nObjectEnd\nObjectInstance \"plant\"\n");
    EXPECT_FALSE(hasWarning(c, "alpha"));
    const Json& shapes = c.document["shapes"];
    EXPECT_EQ(shapes[0]["alpha"], 0.25);
    EXPECT_EQ(shapes[1]["alpha"]["type"], "checkerboard");
    EXPECT_FALSE(shapes[2].contains("alpha"));
    EXPECT_EQ(shapes[3]["alpha"], 0.0);
    EXPECT_EQ(c.document["prototypes"]["plant"]["alpha"]["type"], "checkerboard");
    const Scene scene = buildPbrtScene(c, "test.pbrt");
    ASSERT_EQ(scene.meshes.size(), 4u);  // the sphere with a cut-out is triangles
    EXPECT_EQ(scene.spheres.size(), 0u);
    ASSERT_TRUE(scene.meshes[0].alpha);
    EXPECT_FLOAT_EQ(scene.meshes[0].alpha->coverage({}), 0.25f);
    EXPECT_TRUE(scene.meshes[1].alpha);
    EXPECT_FALSE(scene.meshes[2].alpha);
    ASSERT_EQ(scene.prototypes.size(), 1u);
    EXPECT_TRUE(scene.prototypes[0].alpha);
    const InputError e = testing::catchInputError(
        [] { convert("WorldBegin\nShape \"disk\" \"texture alpha\" \"nothing\"\n"); });
    EXPECT_CONTAINS(e.what(), "unknown float texture \"nothing\"");
}

TEST(PbrtMapping, IncludedFilesAreCoveredByTheSceneHash) {
    const fs::path dir = fs::temp_directory_path() / "penumbra_pbrt_hash_test";
    fs::create_directories(dir);
    std::ofstream(dir / "geometry.pbrt") << "Shape \"sphere\"\n";
    std::ofstream(dir / "scene.pbrt") << "WorldBegin\nInclude \"geometry.pbrt\"\n";
    std::vector<std::string> warnings;
    const Scene scene = loadSceneFile(dir / "scene.pbrt", {{}, &warnings});
    ASSERT_EQ(scene.includedFiles.size(), 1u);
    EXPECT_EQ(scene.includedFiles[0], dir / "geometry.pbrt");
    EXPECT_EQ(scene.spheres.size(), 1u);
    fs::remove_all(dir);
}

TEST(PbrtMapping, APatchChangesTheConvertedScene) {
    const fs::path dir = fs::temp_directory_path() / "penumbra_pbrt_patch_test";
    fs::create_directories(dir);
    std::ofstream(dir / "scene.pbrt")
        << "WorldBegin\nMakeNamedMaterial \"metal\" \"string type\" \"conductor\" "
           "\"float roughness\" 0.01\nNamedMaterial \"metal\"\nShape \"sphere\"\n";
    std::ofstream(dir / "patch.json")
        << R"({"integrator": {"max_depth": 1}, "materials": {"metal": {"tint": 0.3}}})";
    std::vector<std::string> warnings;
    const Scene scene = loadSceneFile(dir / "scene.pbrt", {dir / "patch.json", &warnings});
    EXPECT_EQ(scene.integrator.maxDepth, 1);
    ASSERT_TRUE(std::holds_alternative<RoughConductor>(scene.materials[0].model()));
    EXPECT_FLOAT_EQ(std::get<RoughConductor>(scene.materials[0].model()).tint.r, 0.3f);
    // The patch is part of the scene: the film's scene hash covers it.
    ASSERT_EQ(scene.includedFiles.size(), 1u);
    EXPECT_EQ(scene.includedFiles[0], dir / "patch.json");
    fs::remove_all(dir);
}

}  // namespace
}  // namespace penumbra::pbrt

namespace penumbra::pbrt {
namespace {

// Hair: pbrt-v4's curve shape (Bezier and B-spline, degree 3 and 2, flat, cylinder and ribbon,
// width, width0 and width1) under transforms, the curves of one material and type gathered into one
// set (a hair file's thousands of Shape "curve" lines), and the hair material's parameters.
TEST(PbrtMapping, CurvesAndTheHairMaterial) {
    const auto c = convert(
        kCamera +
        "WorldBegin\nMaterial \"hair\" \"float eumelanin\" 0.8 \"float beta_m\" 0.25\n"
        "AttributeBegin\nTranslate 1 0 0\nScale 2 2 2\n"
        "Shape \"curve\" \"point3 P\" [0 0 0  0 1 0  0 2 0  0 3 0] \"float width0\" 0.2 \"float width1\" 0.1 "
        "\"string type\" \"cylinder\"\n"
        "AttributeEnd\n"
        "Shape \"curve\" \"point3 P\" [0 0 0  0 1 0  0 2 0  0 3 0] \"float width\" 0.1 \"string type\" "
        "\"cylinder\"\n"
        "Shape \"curve\" \"point3 P\" [0 0 0  1 1 0  2 0 0] \"integer degree\" 2 \"string type\" "
        "\"cylinder\" "
        "\"float width\" 0.05\n"
        "Shape \"curve\" \"point3 P\" [0 0 0  1 0 0  2 0 0  3 0 0  4 0 0] \"string basis\" \"bspline\" "
        "\"string type\" \"ribbon\" \"normal N\" [0 0 1  0 0 1  0 1 0]\n");
    const Json& shapes = c.document["shapes"];
    ASSERT_EQ(shapes.size(), 2u);
    const Json& hair = shapes[0];
    EXPECT_EQ(hair["type"], "curves");
    EXPECT_EQ(hair["curve_type"], "cylinder");
    EXPECT_EQ(hair["curve_sizes"], Json::array({4, 4, 4}));
    // The first curve's widths scaled by its transform's scale, 2.
    EXPECT_EQ(hair["curve_widths"], Json::parse("[[0.4, 0.2], [0.1, 0.1], [0.05, 0.05]]"));
    EXPECT_EQ(hair["points"][1], Json::parse("[1.0, 2.0, 0.0]"));  // (0, 1, 0) scaled by 2, moved by 1 in x
    // The quadratic as a cubic: the same curve, through (1, 0.5, 0) at its middle.
    std::array<Vec3d, 4> q;
    for (int k = 0; k < 4; ++k)
        q[k] = {hair["points"][8 + k][0].get<double>(), hair["points"][8 + k][1].get<double>(),
                hair["points"][8 + k][2].get<double>()};
    const Vec3d middle = (q[0] + q[1] * 3.0 + q[2] * 3.0 + q[3]) * 0.125;
    EXPECT_NEAR(middle.x, 1.0, 1e-12);
    EXPECT_NEAR(middle.y, 0.5, 1e-12);
    const Json& ribbon = shapes[1];
    EXPECT_EQ(ribbon["curve_type"], "ribbon");
    EXPECT_EQ(ribbon["basis"], "bspline");
    EXPECT_EQ(ribbon["normals"].size(), 3u);
    EXPECT_EQ(ribbon["curve_widths"], Json::parse("[[1.0, 1.0]]"));  // pbrt-v4's default width
    const Json& material = c.document["materials"][hair["material"].get<std::string>()];
    EXPECT_EQ(material["type"], "hair");
    EXPECT_EQ(material["eumelanin"], 0.8);
    EXPECT_EQ(material["beta_m"], 0.25);
    EXPECT_FALSE(hasWarning(c, "not supported"));

    const Scene scene = buildScene(c.document, "test.pbrt");
    ASSERT_EQ(scene.curves.size(), 2u);
    EXPECT_EQ(scene.curves[0].segmentCount(), 3u);
    EXPECT_EQ(scene.curves[1].segmentCount(), 2u);
    EXPECT_TRUE(scene.materials[scene.curves[0].material].isFiber());

    const InputError odd = testing::catchInputError(
        [&] { convert("WorldBegin\nShape \"curve\" \"point3 P\" [0 0 0 1 1 1 2 2 2 3 3 3 4 4 4]\n"); });
    EXPECT_CONTAINS(odd.what(), "test.pbrt:2");
    EXPECT_CONTAINS(odd.message(), "5 control points do not make whole segments of a degree 3 bezier curve");
}

}  // namespace
}  // namespace penumbra::pbrt
