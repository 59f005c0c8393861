// What `penumbra render` and `merge` tell the user and what `--film` writes: the description of
// the render before it starts, the summary of a resumed run (this run's samples), the command
// that continues a stopped render (with every option that decides the film), and the beauty-only
// film (smaller, the same beauty, refused by resume and merge).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "film/film_exr.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::runPenumbra;
using testing::RunResult;
using testing::runShell;

const char* kScene = R"({
  "camera": {"look_from": [0, 1.5, 3], "look_at": [0, 0.3, 0], "fov": 45},
  "film": {"resolution": [20, 16], "spp": 4},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
  "shapes": [
    {"type": "quad", "corner": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "grey"},
    {"type": "sphere", "center": [0.5, 0.3, 0], "radius": 0.3, "material": "grey",
     "emission": {"radiance": [2, 2, 2]}}
  ]
})";

class RenderOutput : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-render-output-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        scene_ = (dir_ / "scene.json").string();
        std::ofstream(scene_) << kScene;
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    RunResult render(const std::string& arguments) {
        return runPenumbra("render " + scene_ + " " + arguments);
    }

    fs::path dir_;
    std::string scene_;
};

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

std::vector<float> readChannels(const std::string& file, int channels) {
    auto in = OIIO::ImageInput::open(file);
    if (!in) return {};
    std::vector<float> pixels(size_t(in->spec().width) * in->spec().height * channels);
    in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data());
    return pixels;
}

TEST_F(RenderOutput, SaysWhatItRendersBeforeStarting) {
    const RunResult r = render("--no-display --threads 1 --accel bvh -o " + path("a.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const size_t description = r.output.find("rendering " + scene_ + ": 20x16");
    ASSERT_NE(description, std::string::npos) << r.output;
    EXPECT_LT(description, r.output.find("rendered ")) << r.output;
    for (const char* part :
         {"samples 0:4 (4 spp)", "stratified sampler", "seed 0", "1 thread,", "bvh", "film full"})
        EXPECT_TRUE(contains(r, part)) << part << "\n" << r.output;
}

TEST_F(RenderOutput, ResumedRunReportsTheSamplesItRendered) {
    ASSERT_EQ(render("-q --no-display --spp 2 -o " + path("a.exr")).exitCode, 0);
    const RunResult r = render("--no-display --spp 6 --resume " + path("a.exr") + " -o " + path("a.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r, "rendered 20x16, samples 2:6 (4 spp; the film then holds 0:6)")) << r.output;
}

// A stopped render prints the command that continues it, with the options it was given that decide
// which samples the film holds.
TEST_F(RenderOutput, ContinueCommandKeepsTheFilmsOptions) {
    const std::string out = path("run.exr");
    const std::string script = std::string(PENUMBRA_BINARY) + " render " + scene_ +
                               " -q --no-display --res 12x10 --seed 7 --sampler independent -o " + out +
                               " --spp 1000000 --pass-size 2 --checkpoint 0 & pid=$!; "
                               "i=0; while [ ! -f " +
                               out +
                               " ] && [ $i -lt 3000 ]; do sleep 0.01; i=$((i+1)); done; "
                               "kill -TERM $pid; wait $pid; echo \"exit=$?\"";
    const RunResult r = runShell("sh -c '" + script + "'");
    ASSERT_TRUE(contains(r, "exit=143")) << r.output;
    const size_t hint = r.output.find("continue with: penumbra render " + scene_);
    ASSERT_NE(hint, std::string::npos) << r.output;
    const std::string command = r.output.substr(hint);
    for (const char* option :
         {"--res 12x10", "--seed 7", "--sampler independent", "--spp 1000000", "--resume "})
        EXPECT_NE(command.find(option), std::string::npos) << option << "\n" << command;
}

TEST_F(RenderOutput, MergeOfOnePartSaysFilm) {
    ASSERT_EQ(render("-q --no-display --samples 0:2 -o " + path("p.exr")).exitCode, 0);
    const RunResult r = runPenumbra("merge " + path("p.exr") + " --no-display -o " + path("m.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r, "merged 1 film: 20x16")) << r.output;
}

// --film beauty: the same beauty and AOVs as --film full, without the sums: a smaller file that
// resume and merge refuse with a message naming the option.
TEST_F(RenderOutput, BeautyFilmHoldsTheSameImageWithoutTheSums) {
    ASSERT_EQ(render("-q --no-display --spp 16 -o " + path("full.exr")).exitCode, 0);
    ASSERT_EQ(render("-q --no-display --spp 16 --film beauty -o " + path("beauty.exr")).exitCode, 0);
    EXPECT_LT(fs::file_size(path("beauty.exr")) * 3, fs::file_size(path("full.exr")) * 2);
    const std::vector<float> full = readChannels(path("full.exr"), 14),
                             beauty = readChannels(path("beauty.exr"), 14);
    ASSERT_EQ(full.size(), size_t(20 * 16 * 14));
    EXPECT_EQ(full, beauty);
    EXPECT_FALSE(isPenumbraFilm(path("beauty.exr")));
    try {
        readFilmExr(path("beauty.exr"));
        FAIL() << "a beauty-only file read as a film";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--film beauty"), std::string::npos) << e.what();
    }
    const RunResult resume =
        render("-q --no-display --spp 20 --resume " + path("beauty.exr") + " -o " + path("r.exr"));
    EXPECT_NE(resume.exitCode, 0);
    EXPECT_TRUE(contains(resume, "--film beauty")) << resume.output;
    const RunResult merge =
        runPenumbra("merge " + path("beauty.exr") + " -q --no-display -o " + path("m.exr"));
    EXPECT_NE(merge.exitCode, 0);
    EXPECT_TRUE(contains(merge, "--film beauty")) << merge.output;
    EXPECT_FALSE(fs::exists(path("r.exr")));
    EXPECT_FALSE(fs::exists(path("m.exr")));
}

TEST_F(RenderOutput, BeautyFilmRefusesWhatNeedsTheSums) {
    for (const std::string& options :
         std::vector<std::string>{"--samples 0:2", "--checkpoint 1", "--resume " + path("x.exr")}) {
        const RunResult r = render("-q --no-display --film beauty " + options + " -o " + path("b.exr"));
        EXPECT_EQ(r.exitCode, 1) << options;
        EXPECT_TRUE(contains(r, "--film beauty")) << options << "\n" << r.output;
        EXPECT_FALSE(fs::exists(path("b.exr"))) << options;
    }
    EXPECT_NE(render("-q --no-display --film half -o " + path("b.exr")).exitCode, 0);
}

// A view the config does not have is refused before the render, with the views it has.
TEST_F(RenderOutput, UnknownViewIsRefusedBeforeRendering) {
    const RunResult r = render("--spp 1000000 --view Filmc -o " + path("v.exr"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_TRUE(contains(r, "unknown OpenColorIO view 'Filmc'")) << r.output;
    EXPECT_TRUE(contains(r, "'Filmic'")) << r.output;
    EXPECT_FALSE(contains(r, "rendering ")) << r.output;
    EXPECT_FALSE(fs::exists(path("v.exr")));
}

// The folder of linearised sRGB textures is removed at exit; one that a killed render left
// ("penumbra-textures-<pid>-...", its process gone, untouched for a minute) is removed by the next
// render that converts a texture, and a folder of a live process is kept.
TEST_F(RenderOutput, TextureFolderOfAKilledRenderIsRemovedByTheNext) {
    const fs::path temporary = dir_ / "tmp";
    const RunResult exited = runShell("sh -c 'echo $$'");
    ASSERT_EQ(exited.exitCode, 0);
    const std::string deadPid = exited.output.substr(0, exited.output.find('\n'));
    const fs::path stale = temporary / ("penumbra-textures-" + deadPid + "-a1b2c3");
    const fs::path live = temporary / ("penumbra-textures-" + std::to_string(::getpid()) + "-d4e5f6");
    for (const fs::path& folder : {stale, live}) {
        fs::create_directories(folder);
        std::ofstream(folder / "0.exr") << "left behind";
        fs::last_write_time(folder, fs::file_time_type::clock::now() - std::chrono::minutes(5));
    }
    std::ofstream(path("textured.json")) << R"({
      "camera": {"look_from": [0, 1.5, 3], "look_at": [0, 0, 0], "fov": 45},
      "film": {"resolution": [8, 8], "spp": 1},
      "materials": {"floor": {"type": "lambert", "albedo": {"type": "image", "file": ")"
                                         << PENUMBRA_SOURCE_DIR << R"(/scenes/textures/floor.png"}}},
      "shapes": [{"type": "quad", "corner": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "floor"}],
      "environment": {"type": "constant", "radiance": [1, 1, 1]}
    })";
    const RunResult r = runShell("TMPDIR=" + temporary.string() + " " PENUMBRA_BINARY " render " +
                                 path("textured.json") + " -q --no-display -o " + path("t.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live / "0.exr"));
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(temporary))
        left.push_back(entry.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{live.filename().string()});
}

}  // namespace
}  // namespace penumbra
