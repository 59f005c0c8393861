// The `penumbra` program end to end: bad input gives a clear message naming the place, a
// non-zero exit status and no output file; good input writes the EXR and the PNG.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using penumbra::testing::runPenumbra;
using penumbra::testing::RunResult;

class CommandLine : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ =
            fs::temp_directory_path() /
            ("penumbra-cli-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path write(const std::string& name, const std::string& text) {
        const fs::path path = dir_ / name;
        std::ofstream(path) << text;
        return path;
    }
    // Runs `render` on a scene text and checks the failure contract.
    RunResult expectRenderFailure(const std::string& sceneText, const std::string& extraArguments = "") {
        const fs::path scene = write("scene.json", sceneText);
        const fs::path output = dir_ / "out" / "image.exr";
        RunResult r =
            runPenumbra("render " + scene.string() + " -o " + output.string() + " " + extraArguments);
        EXPECT_NE(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("penumbra: error: "), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(output)) << "an output file was left behind";
        EXPECT_FALSE(fs::exists(dir_ / "out" / "image.png")) << "an output file was left behind";
        if (fs::exists(dir_ / "out")) {
            EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "temporary files were left behind";
        }
        return r;
    }
    fs::path dir_;
};

// A valid little scene: a lit Lambert quad seen by a pinhole camera.
const char* kGoodScene = R"({
  // comments are allowed
  "camera": {"look_from": [0, 1, 3], "look_at": [0, 0, 0], "fov": 40},
  "film": {"resolution": [16, 12], "spp": 2},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
  "shapes": [{"type": "quad", "corner": [-1, 0, 1], "edge1": [2, 0, 0], "edge2": [0, 0, -2], "material": "grey"}],
  "lights": [{"type": "point", "position": [0, 2, 0], "intensity": [5, 5, 5]}]
})";

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

TEST_F(CommandLine, HelpExplainsEveryRenderOption) {
    const RunResult top = runPenumbra("--help");
    EXPECT_EQ(top.exitCode, 0);
    EXPECT_TRUE(contains(top, "render"));
    const RunResult r = runPenumbra("render --help");
    EXPECT_EQ(r.exitCode, 0);
    for (const char* option :
         {"--spp", "--seed", "--threads", "--res", "--output", "--sampler", "--crop", "--samples"})
        EXPECT_TRUE(contains(r, option)) << option;
}

TEST_F(CommandLine, GoodSceneWritesExrAndPng) {
    const fs::path scene = write("scene.json", kGoodScene);
    const fs::path output = dir_ / "renders" / "quad.exr";
    const RunResult r = runPenumbra("render " + scene.string() + " -o " + output.string() + " --threads 2");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(output));
    EXPECT_TRUE(fs::exists(dir_ / "renders" / "quad.png"));
    EXPECT_TRUE(contains(r, "rays/s")) << r.output;
    for (const auto& entry : fs::directory_iterator(dir_ / "renders"))
        EXPECT_TRUE(entry.path().extension() == ".exr" || entry.path().extension() == ".png") << entry.path();
}

TEST_F(CommandLine, MissingSceneFile) {
    const fs::path missing = dir_ / "no-such-scene.json";
    const RunResult m = runPenumbra("render " + missing.string() + " -o " + (dir_ / "x.exr").string());
    EXPECT_NE(m.exitCode, 0);
    EXPECT_TRUE(contains(m, "no-such-scene.json")) << m.output;
    EXPECT_FALSE(fs::exists(dir_ / "x.exr"));
}

TEST_F(CommandLine, JsonSyntaxErrorNamesLineAndColumn) {
    const RunResult r = expectRenderFailure("{\n  \"film\": {\"spp\": 4,}\n}\n");
    EXPECT_TRUE(contains(r, "scene.json:2:")) << r.output;
}

TEST_F(CommandLine, UnknownKeyNamesItsPointer) {
    const RunResult r = expectRenderFailure(R"({"film": {"resolution": [4, 4], "sppp": 4}})");
    EXPECT_TRUE(contains(r, "/film/sppp")) << r.output;
}

TEST_F(CommandLine, UnknownMaterial) {
    const RunResult r = expectRenderFailure(R"({
      "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "gold"}]})");
    EXPECT_TRUE(contains(r, "/shapes/0/material")) << r.output;
    EXPECT_TRUE(contains(r, "gold")) << r.output;
}

TEST_F(CommandLine, MissingMeshFile) {
    const RunResult r = expectRenderFailure(R"({
      "materials": {"grey": {"type": "lambert"}},
      "shapes": [{"type": "mesh_file", "file": "meshes/absent.obj", "material": "grey"}]})");
    EXPECT_TRUE(contains(r, "absent.obj")) << r.output;
}

TEST_F(CommandLine, MalformedObj) {
    write("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n");
    const RunResult r = expectRenderFailure(R"({
      "materials": {"grey": {"type": "lambert"}},
      "shapes": [{"type": "mesh_file", "file": "broken.obj", "material": "grey"}]})");
    EXPECT_TRUE(contains(r, "broken.obj")) << r.output;
}

TEST_F(CommandLine, MalformedPly) {
    write("broken.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0\n1 0\n");
    const RunResult r = expectRenderFailure(R"({
      "materials": {"grey": {"type": "lambert"}},
      "shapes": [{"type": "mesh_file", "file": "broken.ply", "material": "grey"}]})");
    EXPECT_TRUE(contains(r, "broken.ply")) << r.output;
}

TEST_F(CommandLine, NanVertex) {
    write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
    const RunResult r = expectRenderFailure(R"({
      "materials": {"grey": {"type": "lambert"}},
      "shapes": [{"type": "mesh_file", "file": "nan.obj", "material": "grey"}]})");
    EXPECT_TRUE(contains(r, "nan.obj")) << r.output;
    EXPECT_TRUE(contains(r, "non-finite")) << r.output;
}

TEST_F(CommandLine, IndexOutOfRange) {
    const RunResult r = expectRenderFailure(R"({
      "materials": {"grey": {"type": "lambert"}},
      "shapes": [{"type": "triangle_mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [0, 1, 3],
                  "material": "grey"}]})");
    EXPECT_TRUE(contains(r, "/shapes/0/indices/2")) << r.output;
}

TEST_F(CommandLine, ZeroSppInSceneAndOnCommandLine) {
    const RunResult inScene = expectRenderFailure(R"({"film": {"spp": 0}})");
    EXPECT_TRUE(contains(inScene, "/film/spp")) << inScene.output;
    const RunResult onCommandLine = expectRenderFailure(kGoodScene, "--spp 0");
    EXPECT_TRUE(contains(onCommandLine, "--spp")) << onCommandLine.output;
}

TEST_F(CommandLine, ZeroResolutionInSceneAndOnCommandLine) {
    const RunResult inScene = expectRenderFailure(R"({"film": {"resolution": [0, 10]}})");
    EXPECT_TRUE(contains(inScene, "/film/resolution")) << inScene.output;
    const RunResult onCommandLine = expectRenderFailure(kGoodScene, "--res 0x10");
    EXPECT_TRUE(contains(onCommandLine, "--res")) << onCommandLine.output;
}

TEST_F(CommandLine, UnwritableOutputLeavesNothing) {
    const fs::path scene = write("scene.json", kGoodScene);
    write("file", "not a folder");
    const RunResult r = runPenumbra("render " + scene.string() + " -o " + (dir_ / "file" / "x.exr").string());
    EXPECT_NE(r.exitCode, 0);
    EXPECT_TRUE(contains(r, "penumbra: error: ")) << r.output;
}

}  // namespace

namespace {

// Every subcommand's help fits 100 columns (descriptions wrapped at words), and the wrapping
// keeps every word of a description.
TEST(CommandLineHelp, NoLineIsWiderThanAHundredColumns) {
    for (const char* command :
         {"", "render", "merge", "submit", "status", "convert", "converge", "crosscheck"}) {
        const RunResult r = runPenumbra(std::string(command) + " --help");
        EXPECT_EQ(r.exitCode, 0) << command << ": " << r.output;
        size_t start = 0, widest = 0;
        while (start < r.output.size()) {
            size_t end = r.output.find('\n', start);
            if (end == std::string::npos) end = r.output.size();
            widest = std::max(widest, end - start);
            start = end + 1;
        }
        EXPECT_LE(widest, 100u) << command << ":\n" << r.output;
    }
    const RunResult render = runPenumbra("render --help");
    // A long description, whole: its words in order, whatever the line breaks.
    std::string flattened;
    for (const char c : render.output) flattened += (c == '\n' || c == ' ') ? ' ' : c;
    std::string collapsed;
    for (const char c : flattened)
        if (!(c == ' ' && !collapsed.empty() && collapsed.back() == ' ')) collapsed += c;
    EXPECT_NE(
        collapsed.find("What the EXR holds: full (default: image, AOVs and the exact sums; resumable and "
                       "mergeable, about 100 bytes a pixel)"),
        std::string::npos)
        << render.output;
}

}  // namespace
