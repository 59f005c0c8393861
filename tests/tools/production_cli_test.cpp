// Production output through the `penumbra` program: resume, merge and checkpoints give the same
// film bit for bit as one render (through the EXR, so the sums must survive it losslessly), and
// bad input (parts of different renders, overlapping samples, files that are not ours, a
// reference of another size) stops with a clear error and overwrites nothing.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "film/film_exr.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::runPenumbra;
using testing::RunResult;
using testing::runShell;

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

// A floor, a box casting a soft shadow from an area light, and a sphere.
const char* kScene = R"({
  "camera": {"look_from": [0, 1.5, 3], "look_at": [0, 0.3, 0], "fov": 45},
  "film": {"resolution": [20, 16], "spp": 4},
  "integrator": {"max_depth": 3},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}, "black": {"type": "lambert", "albedo": 0}},
  "shapes": [
    {"type": "quad", "corner": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "grey"},
    {"type": "sphere", "center": [0.5, 0.3, 0], "radius": 0.3, "material": "grey"},
    {"type": "quad", "corner": [-0.6, 0, -0.3], "edge1": [0.5, 0, 0], "edge2": [0, 0.6, 0], "material": "grey"},
    {"type": "quad", "corner": [-1, 2, -1], "edge1": [0, 0, 2], "edge2": [1, 0, 0], "material": "black",
     "emission": {"radiance": [4, 4, 4]}}
  ]
})";

class Production : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-production-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        scene_ = write("scene.json", kScene);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text) {
        const fs::path path = dir_ / name;
        std::ofstream(path) << text;
        return path.string();
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    // Renders and checks success.
    void render(const std::string& arguments, const std::string& output, const std::string& scene = "") {
        const RunResult r = runPenumbra("render " + (scene.empty() ? scene_ : scene) +
                                        " -q --no-display -o " + path(output) + " " + arguments);
        ASSERT_EQ(r.exitCode, 0) << r.output;
    }
    std::string readText(const std::string& name) const {
        std::ifstream in(dir_ / name);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    // Runs a command that must fail with a clear message and leave `out.exr` (created here
    // beforehand) as it was, with no temporary file beside it.
    RunResult expectFailure(const std::string& arguments, const std::string& mention) {
        write("out.exr", "precious");
        size_t filesBefore = 0;
        for (const auto& e : fs::directory_iterator(dir_)) filesBefore += e.is_regular_file();
        const RunResult r = runPenumbra(arguments);
        EXPECT_EQ(r.exitCode, 1) << r.output;
        EXPECT_TRUE(contains(r, "penumbra: error: ")) << r.output;
        EXPECT_TRUE(contains(r, mention)) << "expected '" << mention << "' in: " << r.output;
        EXPECT_EQ(readText("out.exr"), "precious") << "the output was overwritten";
        size_t filesAfter = 0;
        for (const auto& e : fs::directory_iterator(dir_)) filesAfter += e.is_regular_file();
        EXPECT_EQ(filesAfter, filesBefore) << "a file was left behind";
        return r;
    }

    fs::path dir_;
    std::string scene_;
};

TEST_F(Production, ResumeIsBitIdenticalToOneRender) {
    // With a crop, another seed and sampler, resumed onto the same file in passes of 2.
    const std::string opts = "--crop 3,17,2,11 --seed 9 --sampler independent ";
    render(opts + "--spp 9", "once.exr");
    render(opts + "--spp 4", "film.exr");
    EXPECT_FALSE(readFilmExr(path("film.exr")).film.identicalTo(readFilmExr(path("once.exr")).film));
    render(opts + "--spp 9 --pass-size 2 --resume " + path("film.exr"), "film.exr");
    const FilmFile once = readFilmExr(path("once.exr"));
    const FilmFile resumed = readFilmExr(path("film.exr"));
    EXPECT_TRUE(resumed.film.identicalTo(once.film));
    EXPECT_EQ(resumed.metadata.firstSample, 0u);
    EXPECT_EQ(resumed.metadata.endSample, 9u);
    EXPECT_EQ(resumed.metadata.samplesPerPixel, 9);
    ASSERT_TRUE(resumed.metadata.crop.has_value());
    EXPECT_TRUE((*resumed.metadata.crop == PixelWindow{3, 17, 2, 11}));
}

// A scene's film.crop_window (pbrt-v4's cropwindow) renders the pixels --crop names, rounded as
// pbrt-v4 rounds them: [0.2, 0.51] x [0.1, 0.999] of 20 x 16 is x [4, 11), y [2, 16); --crop takes
// its place; a window with no pixel is an error before anything is written.
TEST_F(Production, ASceneCropWindowRendersThePixelsOfItsCrop) {
    std::string cropped = kScene;
    const std::string film = R"("film": {"resolution": [20, 16], "spp": 4)";
    cropped.replace(cropped.find(film), film.size(), film + R"(, "crop_window": [0.2, 0.51, 0.1, 0.999])");
    const std::string scene = write("cropped.json", cropped);
    render("", "window.exr", scene);
    render("--crop 4,11,2,16", "crop.exr");
    const FilmFile window = readFilmExr(path("window.exr"));
    ASSERT_TRUE(window.metadata.crop.has_value());
    EXPECT_TRUE((*window.metadata.crop == PixelWindow{4, 11, 2, 16}));
    EXPECT_TRUE(window.film.identicalTo(readFilmExr(path("crop.exr")).film));
    render("--crop 0,20,0,8", "override.exr", scene);
    EXPECT_TRUE((*readFilmExr(path("override.exr")).metadata.crop == PixelWindow{0, 20, 0, 8}));
    expectFailure("render " + scene + " --res 1x1 -q -o " + path("out.exr"),
                  "film.crop_window [0.2, 0.51, 0.1, 0.999] holds no pixel of the 1x1 image");
}

TEST_F(Production, MergeIsBitIdenticalToOneRender) {
    render("--spp 12", "once.exr");
    render("--samples 0:5", "a.exr");
    render("--samples 5:12 --crop 0,20,0,7", "top.exr");
    render("--samples 5:12 --crop 0,20,7,16", "bottom.exr");
    // Sample ranges and crops at once, the parts in any order: the sums are exact.
    const RunResult r = runPenumbra("merge " + path("top.exr") + " " + path("a.exr") + " " +
                                    path("bottom.exr") + " -q -o " + path("merged.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(path("merged.png")));
    const FilmFile merged = readFilmExr(path("merged.exr"));
    EXPECT_TRUE(merged.film.identicalTo(readFilmExr(path("once.exr")).film));
    EXPECT_EQ(merged.metadata.firstSample, 0u);
    EXPECT_EQ(merged.metadata.endSample, 12u);
    EXPECT_FALSE(merged.metadata.crop.has_value());
}

// SIGTERM: the render finishes its pass, writes the film of the last complete pass and exits
// with 128 + 15; resuming it gives the uninterrupted render.
TEST_F(Production, CheckpointAfterSigtermResumesToTheSameImage) {
    const std::string out = path("run.exr");
    const std::string script = std::string(PENUMBRA_BINARY) + " render " + scene_ + " -q --no-display -o " +
                               out +
                               " --spp 1000000 --pass-size 2 --checkpoint 0 & pid=$!; "
                               "i=0; while [ ! -f " +
                               out +
                               " ] && [ $i -lt 3000 ]; do sleep 0.01; i=$((i+1)); done; "
                               "kill -TERM $pid; wait $pid; echo \"exit=$?\"";
    const RunResult r = runShell("sh -c '" + script + "'");
    ASSERT_TRUE(contains(r, "exit=143")) << r.output;
    EXPECT_TRUE(contains(r, "stopped by signal 15")) << r.output;
    EXPECT_TRUE(contains(r, "--resume")) << r.output;

    const FilmFile interrupted = readFilmExr(out);
    const uint32_t k = interrupted.metadata.endSample;
    EXPECT_EQ(interrupted.metadata.firstSample, 0u);
    ASSERT_GE(k, 2u);
    ASSERT_LT(k, 1000000u);
    EXPECT_EQ(k % 2, 0u) << "a pass boundary";
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 20; ++x) ASSERT_EQ(interrupted.film.at(x, y).sampleCount, k);

    const std::string spp = std::to_string(k + 3);
    render("--spp " + spp + " --resume " + out, "resumed.exr");
    render("--spp " + spp, "once.exr");
    EXPECT_TRUE(readFilmExr(path("resumed.exr")).film.identicalTo(readFilmExr(path("once.exr")).film));
}

// Every kind of mismatch is checked through the API in merge_test.cpp; here the command line's
// side: the message, the exit status, and nothing written.
TEST_F(Production, MergingPartsOfDifferentRendersFails) {
    const std::string other = write("other.json", std::string(kScene) + "\n// another scene\n");
    ASSERT_EQ(runPenumbra("render " + scene_ + " -q --samples 0:2 -o " + path("a.exr")).exitCode,
              0);  // and a.png
    render("--samples 2:4", "other.exr", other);
    const std::string merge = "merge " + path("a.exr") + " ";
    const std::string out = " -o " + path("out.exr");
    expectFailure(merge + path("other.exr") + out, "different scenes");
    expectFailure(merge + path("a.exr") + out, "overlap");
    write("notes.txt", "not an image");
    expectFailure(merge + path("notes.txt") + out, "notes.txt");
    expectFailure(merge + path("a.png") + out, "not a film written by penumbra");
    // An EXR of someone else's, and one that claims to be ours but lacks the sums.
    for (const bool claimsToBeOurs : {false, true}) {
        auto exr = OIIO::ImageOutput::create(path("foreign.exr"));
        OIIO::ImageSpec spec(20, 16, 3, OIIO::TypeDesc::FLOAT);
        if (claimsToBeOurs) spec.attribute("penumbra:film", 1);
        const std::vector<float> pixels(20 * 16 * 3, 0.5f);
        ASSERT_TRUE(exr->open(path("foreign.exr"), spec) &&
                    exr->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
        exr->close();
        expectFailure(merge + path("foreign.exr") + out,
                      claimsToBeOurs ? "penumbra:" : "not a film written by penumbra");
    }
}

TEST_F(Production, ResumingSomethingElseFails) {
    render("--spp 3", "part.exr");
    const std::string base = "render " + scene_ + " --spp 8 -o " + path("out.exr") + " --resume ";
    write("notes.txt", "not an image");
    expectFailure(base + path("notes.txt"), "notes.txt");
    expectFailure(base + path("part.exr") + " --seed 4", "--seed 0");
    expectFailure(base + path("part.exr") + " --samples 3:8", "--samples");
    write("scene.json", std::string(kScene) + "\n// edited\n");
    expectFailure(base + path("part.exr"), "different scene");
}

// The scene hash covers the mesh files a scene names: a film rendered before one changed is not
// resumed as if nothing had.
TEST_F(Production, ResumingAfterAMeshFileChangedFails) {
    write("tri.obj", "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nf 1 2 3\n");
    const std::string scene = write("mesh_scene.json", R"({
      "camera": {"look_from": [0, 2, 3], "look_at": [0, 0, 0], "fov": 45},
      "film": {"resolution": [20, 16], "spp": 4},
      "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
      "shapes": [{"type": "mesh_file", "file": "tri.obj", "material": "grey"}],
      "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 5}]
    })");
    render("--spp 2", "part.exr", scene);
    const std::string resume = "render " + scene + " -q --no-display --spp 4 -o " + path("out.exr") +
                               " --resume " + path("part.exr");
    const RunResult same = runPenumbra(resume);
    EXPECT_EQ(same.exitCode, 0) << same.output;
    write("tri.obj", "v -1 0 -1\nv 2 0 -1\nv 0 0 1\nf 1 2 3\n");
    expectFailure(resume, "different scene");
}

TEST_F(Production, ConvergeWritesItsReportAndRefusesAReferenceOfAnotherSize) {
    const RunResult ok = runPenumbra("converge " + scene_ +
                                     " --spp 1,2,...,8 --reference-spp 16 --seeds 2 -q -o " + path("study"));
    ASSERT_EQ(ok.exitCode, 0) << ok.output;
    for (const char* file : {"convergence.csv", "convergence.json", "strip.png", "reference.exr"})
        EXPECT_TRUE(fs::exists(dir_ / "study" / file)) << file;
    // 2 samplers x 2 seeds x 4 rungs, and a header.
    const std::string csv = readText("study/convergence.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 17) << csv;
    // The plot needs /usr/bin/python3 with matplotlib; without it the report says so.
    if (runShell("/usr/bin/python3 -c 'import matplotlib'").exitCode == 0) {
        EXPECT_TRUE(fs::exists(dir_ / "study" / "convergence.png"));
    }

    // The rendered reference is reusable; one of another size is refused.
    const RunResult again = runPenumbra("converge " + scene_ + " --spp 1,2 --no-plot -q --reference " +
                                        path("study/reference.exr") + " -o " + path("study2"));
    EXPECT_EQ(again.exitCode, 0) << again.output;
    const RunResult bad = runPenumbra("converge " + scene_ + " --res 24x16 --spp 1,2 --no-plot --reference " +
                                      path("study/reference.exr") + " -o " + path("study3"));
    EXPECT_EQ(bad.exitCode, 1) << bad.output;
    EXPECT_TRUE(contains(bad, "penumbra: error: ")) << bad.output;
    EXPECT_TRUE(contains(bad, "20x16")) << bad.output;
    EXPECT_FALSE(fs::exists(dir_ / "study3" / "convergence.csv"));
}

// Any image with R, G and B channels serves as a reference (read through the image plugin).
TEST_F(Production, ConvergeTakesAReferenceImageOfAnotherRenderer) {
    for (const bool withGreen : {true, false}) {
        auto out = OIIO::ImageOutput::create(path("other.exr"));
        OIIO::ImageSpec spec(20, 16, withGreen ? 3 : 2, OIIO::TypeDesc::FLOAT);
        if (!withGreen) spec.channelnames = {"R", "B"};
        const std::vector<float> pixels(size_t(20) * 16 * spec.nchannels, 0.25f);
        ASSERT_TRUE(out->open(path("other.exr"), spec) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
        out->close();
        const RunResult r = runPenumbra("converge " + scene_ + " --spp 1,2 --no-plot -q --reference " +
                                        path("other.exr") + " -o " + path("study"));
        if (withGreen) {
            EXPECT_EQ(r.exitCode, 0) << r.output;
            EXPECT_NE(readText("study/convergence.json").find(path("other.exr")), std::string::npos);
        } else {
            EXPECT_EQ(r.exitCode, 1) << r.output;
            EXPECT_TRUE(contains(r, "no channel 'G'")) << r.output;
        }
    }
}

// OpenImageIO loads some 260 shared libraries (0.4 s at start-up): the program must not link
// it, and loads the image plugin that does only to write a display image.
TEST_F(Production, OpenImageIoIsLoadedOnlyForTheDisplayImage) {
    const RunResult ldd = runShell(std::string("ldd ") + PENUMBRA_BINARY);
    ASSERT_EQ(ldd.exitCode, 0) << ldd.output;
    EXPECT_TRUE(contains(ldd, "libOpenEXR")) << ldd.output;
    EXPECT_FALSE(contains(ldd, "OpenImageIO")) << ldd.output;

    // LD_DEBUG=files lists every shared object the dynamic loader opens, dlopen included.
    const std::string render =
        "LD_DEBUG=files " + std::string(PENUMBRA_BINARY) + " render " + scene_ + " -q --spp 1 -o ";
    const RunResult noDisplay = runShell(render + path("a.exr") + " --no-display");
    ASSERT_EQ(noDisplay.exitCode, 0) << noDisplay.output;
    EXPECT_FALSE(contains(noDisplay, "penumbra_image_plugin")) << noDisplay.output;
    EXPECT_FALSE(contains(noDisplay, "OpenImageIO")) << noDisplay.output;
    const RunResult display = runShell(render + path("b.exr"));
    ASSERT_EQ(display.exitCode, 0) << display.output;
    EXPECT_TRUE(contains(display, "penumbra_image_plugin")) << display.output;
    EXPECT_TRUE(contains(display, "OpenImageIO")) << display.output;
    EXPECT_TRUE(fs::is_regular_file(dir_ / "b.png"));
}

TEST_F(Production, HelpListsTheNewCommandsAndOptions) {
    const RunResult renderHelp = runPenumbra("render --help");
    for (const char* option : {"--resume", "--checkpoint", "--pass-size"})
        EXPECT_TRUE(contains(renderHelp, option)) << option;
    const RunResult converge = runPenumbra("converge --help");
    for (const char* option :
         {"--spp", "--sampler", "--reference", "--reference-spp", "--seeds", "--freeze", "--res"})
        EXPECT_TRUE(contains(converge, option)) << option;
    EXPECT_EQ(runPenumbra("merge --help").exitCode, 0);
}

}  // namespace
}  // namespace penumbra
