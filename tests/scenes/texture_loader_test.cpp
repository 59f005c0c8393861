// Textures and environments in scene files: what they read into, the errors for missing or
// unreadable images (naming the scene key), and that scenes without images never load the
// texture plugin (nor OpenImageIO with it).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"
#include "textures/texture_plugin_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using testing::catchInputError;

const fs::path kSourceDir = PENUMBRA_SOURCE_DIR;

Scene parseWith(const std::string& materials, const std::string& extra = "") {
    return parseScene(
        R"({"materials": )" + materials + extra +
            R"(, "shapes": [{"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m"}]})",
        kSourceDir / "scenes" / "test.json");
}

TEST(TextureLoader, UntexturedScenesDoNotLoadThePlugin) {
    for (const char* name :
         {"cornell-box.json", "materials.json", "rough-materials.json", "motion-blur.json"})
        loadScene(kSourceDir / "scenes" / name);
    // An OpenEXR environment is read with OpenEXR, not through the plugin.
    const Scene scene =
        parseWith(R"({"m": {"type": "lambert", "albedo": {"type": "checkerboard", "colors": [0, 1]}}})",
                  R"(, "environment": {"type": "image", "file": "textures/sky.exr"})");
    EXPECT_TRUE(scene.environment.hasImage());
    EXPECT_TRUE(scene.materials[0].isTextured());
    EXPECT_FALSE(texturePluginLoaded());
}

TEST(TextureLoader, MirroredEnvironmentRunsItsColumnsTheOtherWay) {
    const Scene plain = parseWith(R"({"m": {"type": "lambert"}})",
                                  R"(, "environment": {"type": "image", "file": "textures/sky.exr"})");
    const Scene mirrored =
        parseWith(R"({"m": {"type": "lambert"}})",
                  R"(, "environment": {"type": "image", "file": "textures/sky.exr", "mirror": true})");
    int differing = 0;
    for (int i = 0; i < 64; ++i) {
        const float phi = 0.1f * float(i), theta = 0.3f + 0.04f * float(i);
        const Vec3f d{std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
        EXPECT_EQ(mirrored.environment.radiance(d), plain.environment.radiance({-d.x, d.y, d.z}));
        if (!(mirrored.environment.radiance(d) == plain.environment.radiance(d))) ++differing;
    }
    EXPECT_GT(differing, 0);  // the sky is not symmetric: the test can see the reflection
}

TEST(TextureLoader, ImageTextureLoadsThePlugin) {
    const Scene scene =
        parseWith(R"({"m": {"type": "lambert", "albedo": {"type": "image", "file": "textures/floor.png"}}})");
    EXPECT_TRUE(scene.materials[0].isTextured());
    EXPECT_TRUE(scene.materials[0].needsFootprint());  // trilinear by default
    EXPECT_TRUE(texturePluginLoaded());
}

TEST(TextureLoader, MissingImageNamesTheKey) {
    const InputError e = catchInputError([] {
        parseWith(
            R"({"m": {"type": "lambert", "albedo": {"type": "image", "file": "textures/no-such.png"}}})");
    });
    EXPECT_EQ(e.where().jsonPointer, "/materials/m/albedo/file");
    EXPECT_CONTAINS(e.message(), "does not exist");
    EXPECT_CONTAINS(e.message(), "no-such.png");
}

TEST(TextureLoader, UnreadableImageNamesTheKey) {
    const fs::path bad = fs::temp_directory_path() / ("penumbra-bad-" + std::to_string(::getpid()) + ".png");
    std::ofstream(bad) << "this is not a PNG";
    const InputError e = catchInputError([&] {
        parseWith(
            R"({"m": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": {"type": "image", "file": ")" +
            bad.string() + R"("}}})");
    });
    EXPECT_EQ(e.where().jsonPointer, "/materials/m/roughness/file");
    EXPECT_CONTAINS(e.message(), "cannot read the image");
    fs::remove(bad);
}

TEST(EnvironmentLoader, MissingOrUnreadableMapNamesTheKey) {
    const InputError missing = catchInputError([] {
        parseWith(R"({"m": {"type": "lambert"}})",
                  R"(, "environment": {"type": "image", "file": "nothing.exr"})");
    });
    EXPECT_EQ(missing.where().jsonPointer, "/environment/file");
    const fs::path bad = fs::temp_directory_path() / ("penumbra-bad-" + std::to_string(::getpid()) + ".exr");
    std::ofstream(bad) << "this is not an EXR";
    const InputError unreadable = catchInputError([&] {
        parseWith(R"({"m": {"type": "lambert"}})",
                  R"(, "environment": {"type": "image", "file": ")" + bad.string() + R"("})");
    });
    EXPECT_EQ(unreadable.where().jsonPointer, "/environment/file");
    EXPECT_CONTAINS(unreadable.message(), "cannot read the OpenEXR image");
    fs::remove(bad);
}

// "mapping": the equal-area map is read as such; it must be square, and other names are refused.
TEST(EnvironmentLoader, MappingIsEquirectangularOrASquareEqualArea) {
    const std::string textures = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/textures/";
    const Scene square =
        parseWith(R"({"m": {"type": "lambert"}})", R"(, "environment": {"type": "image", "file": ")" +
                                                       textures + R"(floor.png", "mapping": "equal_area"})");
    ASSERT_TRUE(square.environment.hasImage());
    EXPECT_EQ(square.environment.image()->mapping, EnvironmentMapping::EqualArea);
    const Scene plain =
        parseWith(R"({"m": {"type": "lambert"}})",
                  R"(, "environment": {"type": "image", "file": ")" + textures + R"(sky.exr"})");
    EXPECT_EQ(plain.environment.image()->mapping, EnvironmentMapping::Equirectangular);
    const InputError notSquare = catchInputError([&] {
        parseWith(R"({"m": {"type": "lambert"}})", R"(, "environment": {"type": "image", "file": ")" +
                                                       textures + R"(sky.exr", "mapping": "equal_area"})");
    });
    EXPECT_EQ(notSquare.where().jsonPointer, "/environment/mapping");
    EXPECT_CONTAINS(notSquare.message(), "512x256");
    const InputError unknown = catchInputError([&] {
        parseWith(R"({"m": {"type": "lambert"}})", R"(, "environment": {"type": "image", "file": ")" +
                                                       textures + R"(sky.exr", "mapping": "octahedral"})");
    });
    EXPECT_EQ(unknown.where().jsonPointer, "/environment/mapping");
    EXPECT_CONTAINS(unknown.message(), "equal_area");
}

TEST(EnvironmentLoader, BackgroundIsTheConstantCase) {
    const Scene a = parseWith(R"({"m": {"type": "lambert"}})", R"(, "background": [0.1, 0.2, 0.3])");
    const Scene b = parseWith(R"({"m": {"type": "lambert"}})",
                              R"(, "environment": {"type": "constant", "radiance": [0.1, 0.2, 0.3]})");
    EXPECT_FALSE(a.environment.hasImage());
    EXPECT_EQ(a.environment.constantRadiance(), b.environment.constantRadiance());
    const InputError both = catchInputError([] {
        parseWith(R"({"m": {"type": "lambert"}})",
                  R"(, "background": 1, "environment": {"type": "constant", "radiance": 1})");
    });
    EXPECT_EQ(both.where().jsonPointer, "/environment");
}

}  // namespace
}  // namespace penumbra
