// What the program writes never lands on what it was not asked to write: `convert` refuses to write
// over the scene it reads and writes only a .json, and a link planted where a temporary would go
// (OUT.partial, once a fixed name in a possibly shared folder) is not followed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using penumbra::testing::runPenumbra;
using penumbra::testing::RunResult;

const char* kPbrtScene = R"(LookAt 0 1 4  0 0 0  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 16 "integer yresolution" 12
WorldBegin
LightSource "point" "rgb I" [5 5 5] "point3 from" [0 3 0]
Shape "trianglemesh" "point3 P" [-2 0 -2 2 0 -2 2 0 2 -2 0 2] "integer indices" [0 2 1 0 3 2]
)";

class OutputSafety : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-output-safety-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        std::ofstream(dir_ / "scene.pbrt") << kPbrtScene;
        std::ofstream(dir_ / "victim.txt") << "someone else's file";
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    static std::string read(const std::string& file) {
        std::ifstream in(file);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    fs::path dir_;
};

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

TEST_F(OutputSafety, ConvertNeverWritesOverItsInputOrAnythingButJson) {
    const RunResult self = runPenumbra("convert " + path("scene.pbrt") + " -o " + path("scene.pbrt"));
    EXPECT_EQ(self.exitCode, 1) << self.output;
    EXPECT_TRUE(contains(self, "expected a path ending in .json")) << self.output;
    EXPECT_EQ(read(path("scene.pbrt")), kPbrtScene);
    // The same file by another name.
    fs::create_symlink(path("scene.pbrt"), path("alias.json"));
    const RunResult alias = runPenumbra("convert " + path("scene.pbrt") + " -o " + path("alias.json"));
    EXPECT_EQ(alias.exitCode, 1) << alias.output;
    EXPECT_TRUE(contains(alias, "is the scene being converted")) << alias.output;
    EXPECT_EQ(read(path("scene.pbrt")), kPbrtScene);
}

TEST_F(OutputSafety, ALinkPlantedAtConvertsOldTemporaryNameIsNotFollowed) {
    fs::create_symlink(path("victim.txt"), path("out.json.partial"));
    const RunResult r = runPenumbra("convert " + path("scene.pbrt") + " -o " + path("out.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(read(path("victim.txt")), "someone else's file");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path("out.json"))));
    const RunResult render =
        runPenumbra("render " + path("out.json") + " --spp 1 -q --no-display -o " + path("out.exr"));
    EXPECT_EQ(render.exitCode, 0) << render.output;
    // Like render -o, convert -o makes the folder it names.
    const RunResult nested =
        runPenumbra("convert " + path("scene.pbrt") + " -o " + path("new/folder/out.json"));
    EXPECT_EQ(nested.exitCode, 0) << nested.output;
    EXPECT_TRUE(fs::exists(path("new/folder/out.json")));
}

TEST_F(OutputSafety, ALinkPlantedAtARendersTemporaryNameIsNotFollowed) {
    // The shell's process number is the one `render` will have after exec.
    const RunResult r = runPenumbra("convert " + path("scene.pbrt") + " -o " + path("scene.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const RunResult render =
        penumbra::testing::runShell("sh -c 'ln -s " + path("victim.txt") + " " + path("out.tmp-") +
                                    "$$.exr && exec " PENUMBRA_BINARY " render " + path("scene.json") +
                                    " --spp 1 -q --no-display -o " + path("out.exr") + "'");
    EXPECT_EQ(render.exitCode, 0) << render.output;
    EXPECT_EQ(read(path("victim.txt")), "someone else's file");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path("out.exr"))));
}

}  // namespace
