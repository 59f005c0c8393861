// Hostile input end to end (tests/data/hostile): the `penumbra` program must stop with
// "penumbra: error: PLACE: what was expected", a non-zero exit status and no output file, where it
// once crashed, hung or wrote a wrong image with exit status 0.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using penumbra::testing::RunResult;
using penumbra::testing::runPenumbra;

const fs::path kHostile = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile";

class HostileInput : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-hostile-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "out");
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path write(const std::string& name, const std::string& text) {
        const fs::path path = dir_ / name;
        std::ofstream(path) << text;
        return path;
    }
    // A small lit scene whose one shape is the mesh file `mesh`.
    fs::path sceneWithMesh(const fs::path& mesh) {
        return write("scene.json", R"({"camera": {"look_from": [0.3, 0.3, 3], "look_at": [0.3, 0.3, 0], "fov": 40},
  "film": {"resolution": [16, 12], "spp": 2},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
  "shapes": [{"type": "mesh_file", "file": ")" + mesh.string() + R"(", "material": "grey"}],
  "lights": [{"type": "point", "position": [0, 2, 2], "intensity": [5, 5, 5]}]})");
    }
    // Runs `penumbra ARGUMENTS` and checks the failure contract: non-zero exit, the error line, and
    // nothing in the output folder.
    RunResult expectFailure(const std::string& arguments) {
        RunResult r = runPenumbra(arguments);
        EXPECT_GT(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("penumbra: error: "), std::string::npos) << r.output;
        EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "an output file was left behind";
        return r;
    }
    std::string output() const { return (dir_ / "out" / "image.exr").string(); }

    fs::path dir_;
};

bool contains(const RunResult& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

TEST_F(HostileInput, ObjFaceBehindLoneCarriageReturn) {
    // Once a SIGSEGV (an index read out of range, an empty vertex buffer given to Embree).
    const RunResult r = expectFailure("render " + sceneWithMesh(kHostile / "cr_only_face.obj").string() +
                                      " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "cr_only_face.obj:2:")) << r.output;
    EXPECT_TRUE(contains(r, "vertex index 1 is out of range")) << r.output;
}

TEST_F(HostileInput, PlyBinaryHeaderWithLoneCarriageReturn) {
    // Once a SIGSEGV inside assimp.
    const RunResult r = expectFailure("render " + sceneWithMesh(kHostile / "cr_end_header_binary.ply").string() +
                                      " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "cr_end_header_binary.ply:9:1: a carriage return")) << r.output;
}

TEST_F(HostileInput, ResumeRefusesACorruptFilm) {
    // flipped_sums.exr: a render of flipped_sums_scene.json with 16 bytes flipped in its RLE sums;
    // once resumed with exit status 0 and most pixels wrong.
    const RunResult r = expectFailure("render " + (kHostile / "flipped_sums_scene.json").string() +
                                      " --spp 8 --resume " + (kHostile / "flipped_sums.exr").string() +
                                      " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "flipped_sums.exr: the film's sums or metadata do not match their checksum")) << r.output;
}

TEST_F(HostileInput, MergeRefusesACorruptFilm) {
    const RunResult r = expectFailure("merge " + (kHostile / "flipped_sums.exr").string() + " -o " + output());
    EXPECT_TRUE(contains(r, "flipped_sums.exr: the film's sums or metadata do not match their checksum")) << r.output;
}

TEST_F(HostileInput, FilmLargerThanTheAvailableMemoryIsRefusedBeforeRendering) {
    // 65536x65536 pixels of 312 bytes (256 of sums, 56 to write the EXR): 1.2 TiB, more than any
    // machine has available.
    const fs::path scene = sceneWithMesh(kHostile / "../scenes/meshes/square.obj");
    const RunResult r = expectFailure("render " + scene.string() + " --res 65536x65536 --no-display -o " + output());
    EXPECT_TRUE(contains(r, "a 65536x65536 film needs 1248.0 GiB of memory; this machine has")) << r.output;
    EXPECT_TRUE(contains(r, "GiB available (of ")) << r.output;
}

TEST_F(HostileInput, ThreadCountIsBounded) {
    // --threads 65537 once rendered, then crashed (SIGSEGV) in TBB's arena teardown.
    const fs::path scene = sceneWithMesh(kHostile / "../scenes/meshes/square.obj");
    RunResult r = expectFailure("render " + scene.string() + " --threads 65537 --no-display -o " + output());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_TRUE(contains(r, "--threads: Value 65537 not in range 0 to 4096")) << r.output;
    r = expectFailure("converge " + scene.string() + " --spp 1 --threads 4097 --no-plot -o " + (dir_ / "out").string());
    EXPECT_TRUE(contains(r, "--threads: Value 4097 not in range 0 to 4096")) << r.output;
}

}  // namespace
