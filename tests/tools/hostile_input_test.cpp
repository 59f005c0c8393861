// Hostile input end to end (tests/data/hostile): the `penumbra` program must stop with
// "penumbra: error: PLACE: what was expected", a non-zero exit status and no output file, where it
// once crashed, hung or wrote a wrong image with exit status 0.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using penumbra::testing::runPenumbra;
using penumbra::testing::RunResult;

const fs::path kHostile = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile";

class HostileInput : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-hostile-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
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
        return write("scene.json",
                     R"({"camera": {"look_from": [0.3, 0.3, 3], "look_at": [0.3, 0.3, 0], "fov": 40},
  "film": {"resolution": [16, 12], "spp": 2},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
  "shapes": [{"type": "mesh_file", "file": ")" +
                         mesh.string() + R"(", "material": "grey"}],
  "lights": [{"type": "point", "position": [0, 2, 2], "intensity": [5, 5, 5]}]})");
    }
    // Runs `penumbra ARGUMENTS` and checks the failure contract: non-zero exit, the error line, and
    // nothing in the output folder. A run that hangs is killed after a minute (and fails).
    RunResult expectFailure(const std::string& arguments) {
        RunResult r = penumbra::testing::runShell(std::string("timeout -s KILL 60 ") + PENUMBRA_BINARY + " " +
                                                  arguments);
        EXPECT_GT(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("penumbra: error: "), std::string::npos) << r.output;
        EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "an output file was left behind";
        return r;
    }
    std::string output() const { return (dir_ / "out" / "image.exr").string(); }

    fs::path dir_;
};

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

TEST_F(HostileInput, ObjFaceBehindLoneCarriageReturn) {
    // Once a SIGSEGV (an index read out of range, an empty vertex buffer given to Embree).
    const RunResult r = expectFailure("render " + sceneWithMesh(kHostile / "cr_only_face.obj").string() +
                                      " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "cr_only_face.obj:2:")) << r.output;
    EXPECT_TRUE(contains(r, "vertex index 1 is out of range")) << r.output;
}

TEST_F(HostileInput, PlyBinaryHeaderWithLoneCarriageReturn) {
    // Once a SIGSEGV inside assimp.
    const RunResult r =
        expectFailure("render " + sceneWithMesh(kHostile / "cr_end_header_binary.ply").string() +
                      " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "cr_end_header_binary.ply:9:1: a carriage return")) << r.output;
}

TEST_F(HostileInput, ResumeRefusesACorruptFilm) {
    // flipped_sums.exr: a render of flipped_sums_scene.json with 16 bytes flipped in its RLE sums;
    // once resumed with exit status 0 and most pixels wrong.
    const RunResult r =
        expectFailure("render " + (kHostile / "flipped_sums_scene.json").string() + " --spp 8 --resume " +
                      (kHostile / "flipped_sums.exr").string() + " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "flipped_sums.exr: the film's sums or metadata do not match their checksum"))
        << r.output;
}

TEST_F(HostileInput, MergeRefusesACorruptFilm) {
    const RunResult r =
        expectFailure("merge " + (kHostile / "flipped_sums.exr").string() + " -o " + output());
    EXPECT_TRUE(contains(r, "flipped_sums.exr: the film's sums or metadata do not match their checksum"))
        << r.output;
}

TEST_F(HostileInput, FilmLargerThanTheAvailableMemoryIsRefusedBeforeRendering) {
    // 65536x65536 pixels of 186 bytes (130 of sums, 56 to write the EXR): 744 GiB, more than any
    // machine has available.
    const fs::path scene = sceneWithMesh(kHostile / "../scenes/meshes/square.obj");
    const RunResult r =
        expectFailure("render " + scene.string() + " --res 65536x65536 --no-display -o " + output());
    EXPECT_TRUE(contains(r, "a 65536x65536 film needs 744.0 GiB of memory; this machine has")) << r.output;
    EXPECT_TRUE(contains(r, "GiB available (of ")) << r.output;
}

TEST_F(HostileInput, ThreadCountIsBounded) {
    // --threads 65537 once rendered, then crashed (SIGSEGV) in TBB's arena teardown.
    const fs::path scene = sceneWithMesh(kHostile / "../scenes/meshes/square.obj");
    RunResult r = expectFailure("render " + scene.string() + " --threads 65537 --no-display -o " + output());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_TRUE(contains(r, "--threads: Value 65537 not in range 0 to 4096")) << r.output;
    r = expectFailure("converge " + scene.string() + " --spp 1 --threads 4097 --no-plot -o " +
                      (dir_ / "out").string());
    EXPECT_TRUE(contains(r, "--threads: Value 4097 not in range 0 to 4096")) << r.output;
}

// Runs `penumbra ARGUMENTS` with `folder` on a tmpfs of `bytes` (in a private user and mount
// namespace, so no root is needed), then lists what the folder holds. Empty when namespaces are
// not available here.
std::string runOnSmallDisk(const fs::path& folder, uintmax_t bytes, const std::string& arguments) {
    if (penumbra::testing::runShell("unshare -rm true").exitCode != 0) return "";
    const std::string command = "unshare -rm sh -c 'mount -t tmpfs -o size=" + std::to_string(bytes) +
                                " tmpfs " + folder.string() + " && " + PENUMBRA_BINARY + " " + arguments +
                                "; echo \"exit status $?\"; echo listing:; ls -A " + folder.string() + "'";
    return penumbra::testing::runShell(command).output;
}

TEST_F(HostileInput, FullDiskFailsTheWriteNamingTheFileAndLeavesNoTemporary) {
    const fs::path scene = sceneWithMesh(kHostile / "../scenes/meshes/square.obj");
    // The EXR's size on a roomy disk, to make a disk that holds it but not the PNG as well.
    const RunResult roomy = runPenumbra("render " + scene.string() + " -o " + (dir_ / "roomy.exr").string());
    ASSERT_EQ(roomy.exitCode, 0) << roomy.output;
    const uintmax_t exrPages = (fs::file_size(dir_ / "roomy.exr") + 4095) / 4096;
    const fs::path disk = dir_ / "disk";
    fs::create_directories(disk);

    // No room for the EXR: an error naming it, and nothing left.
    std::string out =
        runOnSmallDisk(disk, 4096, "render " + scene.string() + " -o " + (disk / "o.exr").string());
    if (out.empty()) GTEST_SKIP() << "user namespaces (unshare -rm) are not available to mount a small tmpfs";
    EXPECT_NE(
        out.find("penumbra: error: " + (disk / "o.exr").string() + ": cannot write the EXR image: write of"),
        std::string::npos)
        << out;
    EXPECT_NE(out.find("No space left on device"), std::string::npos) << out;
    EXPECT_NE(out.find("exit status 1\nlisting:\n"), std::string::npos) << out;
    EXPECT_TRUE(out.ends_with("listing:\n")) << "files were left behind: " << out;

    // Room for the EXR only: once "wrote o.png", exit status 0 and an empty PNG. Now an error
    // naming the PNG; the complete EXR stays, and no temporary.
    out = runOnSmallDisk(disk, exrPages * 4096,
                         "render " + scene.string() + " -o " + (disk / "o.exr").string());
    EXPECT_NE(out.find("penumbra: error: " + (disk / "o.png").string() +
                       ": cannot write the display image: write failed: No space left on device"),
              std::string::npos)
        << out;
    EXPECT_TRUE(out.ends_with("exit status 1\nlisting:\no.exr\n")) << out;
}

TEST_F(HostileInput, SceneThatIsAFifoIsRefusedWithoutBlocking) {
    // Once blocked forever in open(); `timeout` ends the old behaviour as a failure.
    const fs::path fifo = dir_ / "pipe.json";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const RunResult r = expectFailure("render " + fifo.string() + " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "pipe.json: is a FIFO (named pipe), not a regular file")) << r.output;
}

TEST_F(HostileInput, SceneBeyondTheSizeLimitIsRefusedUnread) {
    const fs::path huge = dir_ / "huge.json";
    std::ofstream(huge) << "{";
    fs::resize_file(huge, uint64_t(300) << 20);  // sparse
    const RunResult r = expectFailure("render " + huge.string() + " --no-display -o " + output());
    EXPECT_TRUE(contains(r, "huge.json: the scene file is 300.0 MiB; penumbra reads at most 256.0 MiB"))
        << r.output;
}

TEST_F(HostileInput, PathDepthIsBounded) {
    // Once rendered forever, deaf to SIGTERM (which waits for the end of a pass).
    const RunResult r = expectFailure("render " + (kHostile / "closed_mirror_deep.json").string() +
                                      " --no-display -o " + output());
    EXPECT_TRUE(
        contains(r,
                 "closed_mirror_deep.json: /integrator/max_depth: expected an integer in [0, 1024], found "
                 "2147483647"))
        << r.output;
    const fs::path scene = write("roulette.json", R"({"integrator": {"roulette_start": 1025}})");
    const RunResult r2 = expectFailure("render " + scene.string() + " --no-display -o " + output());
    EXPECT_TRUE(contains(
        r2, "roulette.json: /integrator/roulette_start: expected an integer in [0, 1024], found 1025"))
        << r2.output;
}

// Absurd values that were once accepted without a word: each now names its place and its limit.
TEST_F(HostileInput, AbsurdSceneValuesAreRefused) {
    const std::pair<const char*, const char*> cases[] = {
        {"quad_corner_overflow.json",
         "/shapes/0/corner/0: the coordinate 3e+38 is beyond penumbra's limit of 1e+18 in magnitude"},
        {"quad_beyond_coordinate_limit.json",
         "/shapes/0: vertex 1 (counting from 0) lies at (2e+18, 0, 0), beyond the coordinate limit of 1e+18"},
        {"filter_radius_huge.json",
         "/film/filter/radius: expected a radius > 0 and <= 64 pixels, found 3e+38"},
        {"aperture_radius_huge.json",
         "/camera/aperture_radius: expected a number in [0, 1e+18], found 3e+38"},
    };
    for (const auto& [file, message] : cases) {
        const RunResult r =
            expectFailure("render " + (kHostile / file).string() + " --no-display -o " + output());
        EXPECT_TRUE(contains(r, std::string(file) + ": " + message)) << r.output;
    }
}

TEST_F(HostileInput, AbsurdCommandLineValuesAreRefused) {
    const std::string scene = (kHostile / "../scenes/minimal.json").string();
    // --seed once wrapped (-1 became 2^64 - 1) or saturated (2^64 became 2^64 - 1).
    for (const std::string seed : {"-1", "18446744073709551616"}) {
        const RunResult r =
            expectFailure("render " + scene + " --seed " + seed + " --no-display -o " + output());
        EXPECT_TRUE(
            contains(r, "--seed: expected an integer in [0, 18446744073709551615], got '" + seed + "'"))
            << r.output;
    }
    EXPECT_EQ(runPenumbra("render " + scene + " --seed 18446744073709551615 --no-display -o " +
                          (dir_ / "max-seed.exr").string())
                  .exitCode,
              0);
    // --res once allowed 2^30 a side, while scenes stop at 65536.
    const RunResult r = expectFailure("render " + scene + " --res 65537x2 --no-display -o " + output());
    EXPECT_TRUE(contains(r, "--res: expected an integer in [1, 65536], got '65537'")) << r.output;
}

}  // namespace
