// pbrt-v4 scenes through the `penumbra` program: `render` takes a .pbrt file with the usual
// overrides and prints one warning line per kind; `convert` writes penumbra's JSON only when the
// whole scene is good, and a malformed pbrt file is a FILE:LINE:COLUMN error with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using penumbra::testing::runPenumbra;
using penumbra::testing::RunResult;

class PbrtCommandLine : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-pbrt-cli-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& text) {
        std::ofstream(dir_ / name) << text;
        return dir_ / name;
    }
    fs::path dir_;
};

const char* kScene = R"(Scale -1 1 1
LookAt 0 1 4  0 0 0  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 64 "integer yresolution" 48
Sampler "sobol" "integer pixelsamples" 64
WorldBegin
Attribute "shape" "float radius" 2
Attribute "shape" "float radius" 3
LightSource "point" "rgb I" [5 5 5] "point3 from" [0 3 0]
Shape "trianglemesh" "point3 P" [-2 0 -2 2 0 -2 2 0 2 -2 0 2] "integer indices" [0 2 1 0 3 2]
)";

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

TEST_F(PbrtCommandLine, RenderTakesAPbrtSceneWithOverrides) {
    const fs::path scene = write("scene.pbrt", kScene);
    const RunResult r = runPenumbra("render " + scene.string() + " --res 16x12 --spp 2 --no-display -o " +
                                    (dir_ / "out.exr").string());
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r, "rendered 16x12, samples 0:2")) << r.output;
    EXPECT_TRUE(fs::exists(dir_ / "out.exr"));
    // One line for both, with its first place and the count.
    EXPECT_TRUE(contains(r, "penumbra: warning: " + scene.string() + ":7:1: Attribute is not supported"))
        << r.output;
    EXPECT_TRUE(contains(r, "(2 times)")) << r.output;
}

// Scenes that ask for far more than their size (tests/data/hostile/pbrt-bombs): exit status 1,
// the limit named at the directive that crosses it, nothing written, within seconds (the fan-out
// once ran on without end, the spheres wrote a 360 MiB file).
TEST_F(PbrtCommandLine, BombsAreRefusedWithNothingWritten) {
    const fs::path bombs = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile" / "pbrt-bombs";
    std::string spheres = kScene;
    spheres += "ObjectBegin \"a\"\n";
    for (int i = 0; i < 1000; ++i) spheres += "Shape \"sphere\" \"float radius\" 0.01\n";
    spheres += "ObjectEnd\n";
    for (int i = 0; i < 1000; ++i) spheres += "ObjectInstance \"a\"\n";
    const std::pair<fs::path, std::string> cases[] = {
        {bombs / "include-fan-out" / "main.pbrt", "a pbrt scene reads at most 16384 files"},
        {write("spheres.pbrt", spheres),
         "spheres.pbrt:1078:1: ObjectInstance \"a\" would bring the shapes placed"},
        {bombs / "cr-only-lines.pbrt", "cr-only-lines.pbrt:9:1: sphere: the radius must be > 0"}};
    for (const auto& [scene, message] : cases) {
        for (const std::string& command :
             {"render " + scene.string() + " --no-display -o " + (dir_ / "out.exr").string(),
              "convert " + scene.string() + " -o " + (dir_ / "out.json").string()}) {
            const RunResult r = penumbra::testing::runShell(std::string("timeout -s KILL 60 ") +
                                                            PENUMBRA_BINARY + " " + command);
            EXPECT_EQ(r.exitCode, 1) << command << "\n" << r.output;
            EXPECT_TRUE(contains(r, "penumbra: error: ")) << r.output;
            EXPECT_TRUE(contains(r, message)) << command << "\n" << r.output;
            EXPECT_FALSE(fs::exists(dir_ / "out.exr") || fs::exists(dir_ / "out.json")) << command;
        }
    }
}

// --patch changes the scene for render, converge and crosscheck alike: a film size they report,
// and a radius the scene loader refuses at its place in the patched scene.
TEST_F(PbrtCommandLine, PatchAppliesToRenderConvergeAndCrosscheck) {
    const fs::path scene = write("scene.pbrt", kScene);
    const std::string sphere =
        R"x({"type": "sphere", "center": [0, 0, 0], "material": "pbrt default (diffuse 0.5)", "radius": )x";
    const fs::path good =
        write("good.json", R"({"film": {"resolution": [8, 6]}, "shapes": [)" + sphere + "1}]}");
    const fs::path bad = write("bad.json", R"({"shapes": [)" + sphere + "-1}]}");
    const std::string commands[] = {
        "render " + scene.string() + " --spp 1 --no-display -o " + (dir_ / "out.exr").string(),
        "converge " + scene.string() + " --spp 1,2 --reference-spp 2 -o " + (dir_ / "study").string(),
        "crosscheck " + scene.string() + " --rays 4000"};
    const std::string reports[] = {"rendered 8x6", "reference: 8x6", "100.00000%"};
    for (int i = 0; i < 3; ++i) {
        const RunResult r = runPenumbra(commands[i] + " --patch " + good.string());
        EXPECT_EQ(r.exitCode, 0) << commands[i] << "\n" << r.output;
        EXPECT_TRUE(contains(r, reports[i])) << commands[i] << "\n" << r.output;
        const RunResult refused = runPenumbra(commands[i] + " --patch " + bad.string());
        EXPECT_EQ(refused.exitCode, 1) << commands[i];
        EXPECT_TRUE(contains(refused, "/shapes/0/radius")) << commands[i] << "\n" << refused.output;
    }
}

TEST_F(PbrtCommandLine, ConvertWritesJsonThatRenders) {
    const fs::path scene = write("scene.pbrt", kScene);
    fs::create_directories(dir_ / "json");
    const fs::path json = dir_ / "json" / "scene.json";
    const RunResult r = runPenumbra("convert " + scene.string() + " -o " + json.string());
    EXPECT_EQ(r.exitCode, 0) << r.output;
    ASSERT_TRUE(fs::exists(json));
    const RunResult render = runPenumbra("render " + json.string() + " --res 16x12 --spp 2 --no-display -o " +
                                         (dir_ / "json.exr").string());
    EXPECT_EQ(render.exitCode, 0) << render.output;
}

TEST_F(PbrtCommandLine, AMalformedSceneIsAPlacedErrorAndNothingIsWritten) {
    const fs::path scene = write("bad.pbrt", "WorldBegin\nAttributeBegin\nShape \"sphere\"\n");
    const fs::path json = dir_ / "bad.json";
    const RunResult convert = runPenumbra("convert " + scene.string() + " -o " + json.string());
    EXPECT_NE(convert.exitCode, 0);
    EXPECT_TRUE(
        contains(convert, "penumbra: error: " + scene.string() + ":2:1: AttributeBegin is never closed"))
        << convert.output;
    EXPECT_FALSE(fs::exists(json));
    EXPECT_FALSE(fs::exists(dir_ / "bad.json.partial"));
    const RunResult render = runPenumbra("render " + scene.string() + " -o " + (dir_ / "bad.exr").string());
    EXPECT_NE(render.exitCode, 0);
    EXPECT_TRUE(contains(render, scene.string() + ":2:1: AttributeBegin is never closed")) << render.output;
    EXPECT_FALSE(fs::exists(dir_ / "bad.exr"));
}

}  // namespace
