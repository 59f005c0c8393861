// Adaptive sampling on the command line: `render --adaptive` writes an adaptive film and says
// where the samples went; bad settings are refused with clear messages and nothing written;
// `merge` refuses adaptive films; `converge --adaptive` compares adaptive with fixed at equal error.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "film/film_exr.h"
#include "scenes/scene_loader.h"
#include "tests/support/run_command.h"
#include "tests/support/scene_builders.h"
#include "tools/converge.h"

namespace fs = std::filesystem;

namespace penumbra {
namespace {

using testing::runPenumbra;
using testing::RunResult;

class AdaptiveCommandLine : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-adaptive-cli-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& text) {
        const fs::path path = dir_ / name;
        std::ofstream(path) << text;
        return path;
    }
    fs::path dir_;
};

// A lit quad, half of it in the shadow of a point light's occluder.
const char* kScene = R"({
  "camera": {"look_from": [0, 1, 3], "look_at": [0, 0, 0], "fov": 40},
  "film": {"resolution": [24, 16], "spp": 64},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
  "shapes": [{"type": "quad", "corner": [-1, 0, 1], "edge1": [2, 0, 0], "edge2": [0, 0, -2], "material": "grey"},
             {"type": "quad", "corner": [-0.5, 1.2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "material": "grey",
              "emission": {"radiance": [4, 4, 4]}},
             {"type": "sphere", "center": [0.3, 0.3, 0.2], "radius": 0.3, "material": "grey"}]
})";

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

TEST_F(AdaptiveCommandLine, RenderWritesAnAdaptiveFilm) {
    const fs::path scene = write("scene.json", kScene);
    const fs::path out = dir_ / "a.exr";
    const RunResult r = runPenumbra("render " + scene.string() +
                                    " --adaptive 0.05 --min-spp 8 --no-display -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(contains(r, "adaptive 0.05 (min 8 spp)")) << r.output;
    const FilmFile film = readFilmExr(out);
    ASSERT_TRUE(film.metadata.adaptive);
    EXPECT_EQ(*film.metadata.adaptive, (AdaptiveSettings{0.05f, 8}));
    EXPECT_EQ(film.metadata.endSample, 64u);

    // The scene file's settings, overridden by the command line.
    const fs::path inScene = write(
        "in-scene.json",
        std::string(kScene).replace(std::string(kScene).find("\"spp\": 64}"), 10,
                                    "\"spp\": 64, \"adaptive\": {\"threshold\": 0.1, \"min_spp\": 24}}"));
    ASSERT_EQ(runPenumbra("render " + inScene.string() + " -q --no-display -o " + out.string()).exitCode, 0);
    EXPECT_EQ(readFilmExr(out).metadata.adaptive, (AdaptiveSettings{0.1f, 24}));
    ASSERT_EQ(runPenumbra("render " + inScene.string() + " -q --no-display --adaptive 0.2 -o " + out.string())
                  .exitCode,
              0);
    EXPECT_EQ(readFilmExr(out).metadata.adaptive, (AdaptiveSettings{0.2f, 24}));

    // The absolute criterion, from the command line (its RMSE may exceed 1) and from the scene file.
    const RunResult absolute =
        runPenumbra("render " + inScene.string() +
                    " --no-display --adaptive 2.5 --adaptive-error absolute -o " + out.string());
    ASSERT_EQ(absolute.exitCode, 0) << absolute.output;
    EXPECT_TRUE(contains(absolute, "adaptive 2.5 (image RMSE, min 24 spp)")) << absolute.output;
    EXPECT_EQ(readFilmExr(out).metadata.adaptive, (AdaptiveSettings{2.5f, 24, AdaptiveError::Absolute}));
    const fs::path absoluteScene =
        write("absolute.json",
              std::string(kScene).replace(std::string(kScene).find("\"spp\": 64}"), 10,
                                          "\"spp\": 64, \"adaptive\": {\"threshold\": 0.01, \"error\": "
                                          "\"absolute\"}}"));
    ASSERT_EQ(
        runPenumbra("render " + absoluteScene.string() + " -q --no-display -o " + out.string()).exitCode, 0);
    EXPECT_EQ(readFilmExr(out).metadata.adaptive, (AdaptiveSettings{0.01f, 16, AdaptiveError::Absolute}));
    ASSERT_EQ(runPenumbra("render " + absoluteScene.string() +
                          " -q --no-display --adaptive-error relative -o " + out.string())
                  .exitCode,
              0);
    EXPECT_EQ(readFilmExr(out).metadata.adaptive, (AdaptiveSettings{0.01f, 16, AdaptiveError::Relative}));

    // Merging it is refused.
    const RunResult merge =
        runPenumbra("merge " + out.string() + " --no-display -o " + (dir_ / "m.exr").string());
    EXPECT_NE(merge.exitCode, 0);
    EXPECT_TRUE(contains(merge, "adaptive render")) << merge.output;
    EXPECT_FALSE(fs::exists(dir_ / "m.exr"));
}

TEST_F(AdaptiveCommandLine, AResumedRenderEndsAsOneRender) {
    const fs::path scene = write("scene.json", kScene);
    const std::string common = " --adaptive 0.05 --no-display -q --threads 2 ";
    ASSERT_EQ(runPenumbra("render " + scene.string() + common + "--spp 64 -o " + (dir_ / "once.exr").string())
                  .exitCode,
              0);
    ASSERT_EQ(runPenumbra("render " + scene.string() + common + "--spp 36 -o " + (dir_ / "part.exr").string())
                  .exitCode,
              0);
    const RunResult rest = runPenumbra("render " + scene.string() + common + "--spp 64 --resume " +
                                       (dir_ / "part.exr").string() + " -o " + (dir_ / "part.exr").string());
    ASSERT_EQ(rest.exitCode, 0) << rest.output;
    EXPECT_TRUE(readFilmExr(dir_ / "part.exr").film.identicalTo(readFilmExr(dir_ / "once.exr").film));
    // Another threshold is refused, naming the settings.
    const RunResult other =
        runPenumbra("render " + scene.string() + " --adaptive 0.1 --no-display --spp 64 --resume " +
                    (dir_ / "once.exr").string() + " -o " + (dir_ / "other.exr").string());
    EXPECT_NE(other.exitCode, 0);
    EXPECT_TRUE(contains(other, "adaptive sampling 0.05:16")) << other.output;
    EXPECT_FALSE(fs::exists(dir_ / "other.exr"));
}

// Where the samples went is in the beauty part too (a UINT `spp` channel), also in a beauty-only
// film, and equals the film's own counts.
TEST_F(AdaptiveCommandLine, BeautyPartHoldsEachPixelsSampleCount) {
    const fs::path scene = write("scene.json", kScene);
    const std::string common = "render " + scene.string() + " --adaptive 0.05 --min-spp 8 -q --no-display ";
    ASSERT_EQ(runPenumbra(common + "-o " + (dir_ / "full.exr").string()).exitCode, 0);
    ASSERT_EQ(runPenumbra(common + "--film beauty -o " + (dir_ / "beauty.exr").string()).exitCode, 0);
    const Film film = readFilmExr(dir_ / "full.exr").film;
    uint32_t fewest = UINT32_MAX, most = 0;
    for (const char* file : {"full.exr", "beauty.exr"}) {
        auto in = OIIO::ImageInput::open((dir_ / file).string());
        ASSERT_TRUE(in) << file;
        const OIIO::ImageSpec& spec = in->spec();
        const int spp = spec.channelindex("spp");
        ASSERT_GE(spp, 0) << file;
        EXPECT_EQ(spec.channelformat(spp), OIIO::TypeDesc::UINT) << file;
        std::vector<uint32_t> counts(size_t(spec.width) * spec.height);
        ASSERT_TRUE(in->read_image(0, 0, spp, spp + 1, OIIO::TypeDesc::UINT, counts.data()))
            << in->geterror();
        for (int y = 0; y < spec.height; ++y)
            for (int x = 0; x < spec.width; ++x) {
                const uint32_t count = counts[size_t(y) * spec.width + x];
                EXPECT_EQ(count, film.at(x, y).sampleCount) << file << " pixel " << x << ", " << y;
                fewest = std::min(fewest, count);
                most = std::max(most, count);
            }
    }
    EXPECT_LT(fewest, most);  // some pixels stopped early, others kept sampling
    // A fixed-count render has no such channel: its count is the same everywhere.
    ASSERT_EQ(runPenumbra("render " + scene.string() + " -q --no-display --spp 4 -o " +
                          (dir_ / "fixed.exr").string())
                  .exitCode,
              0);
    EXPECT_LT(OIIO::ImageInput::open((dir_ / "fixed.exr").string())->spec().channelindex("spp"), 0);
}

TEST_F(AdaptiveCommandLine, BadSettingsAreRefused) {
    const fs::path scene = write("scene.json", kScene);
    const fs::path out = dir_ / "x.exr";
    const std::pair<std::string, std::string> cases[] = {
        {"--adaptive 0", "--adaptive: expected a relative standard error > 0 and <= 1"},
        {"--adaptive 1.5", "--adaptive: expected"},
        {"--adaptive nan", "--adaptive"},
        {"--min-spp 8", "--min-spp: the samples before adaptive sampling's first decision"},
        {"--adaptive 0.1 --min-spp 1", "--min-spp: expected an integer in [2,"},
        {"--adaptive 0.1 --samples 8:16", "an adaptive render"},
        {"--adaptive-error absolute", "--adaptive-error: what adaptive sampling's threshold bounds"},
        {"--adaptive 0.1 --adaptive-error sideways",
         "--adaptive-error: expected relative or absolute, got 'sideways'"},
        {"--adaptive 0 --adaptive-error absolute", "--adaptive: expected the image's RMSE, > 0"},
        {"--adaptive 1e19 --adaptive-error absolute",
         "--adaptive: expected the image's RMSE, > 0 and <= 1e+18"},
    };
    for (const auto& [arguments, message] : cases) {
        const RunResult r =
            runPenumbra("render " + scene.string() + " --no-display -o " + out.string() + " " + arguments);
        EXPECT_NE(r.exitCode, 0) << arguments;
        EXPECT_TRUE(contains(r, "penumbra: error: ")) << arguments << ": " << r.output;
        EXPECT_TRUE(contains(r, message)) << arguments << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << arguments;
    }
    const std::pair<std::string, std::string> sceneCases[] = {
        {"\"adaptive\": {\"min_spp\": 8}", "/film/adaptive: adaptive sampling needs a \"threshold\""},
        {"\"adaptive\": {\"threshold\": 0}", "/film/adaptive/threshold"},
        {"\"adaptive\": {\"threshold\": 0.1, \"min_spp\": 1}", "/film/adaptive/min_spp"},
        {"\"adaptive\": {\"threshold\": 0.1, \"minspp\": 8}", "minspp"},
        {"\"adaptive\": {\"threshold\": 0.1, \"error\": \"sideways\"}", "/film/adaptive/error"},
        {"\"adaptive\": {\"threshold\": 1.5}", "a relative standard error > 0 and <= 1"},
        {"\"adaptive\": {\"threshold\": 1e19, \"error\": \"absolute\"}", "/film/adaptive/threshold"},
    };
    for (const auto& [json, message] : sceneCases) {
        std::string text = kScene;
        text.replace(text.find("\"spp\": 64}"), 10, "\"spp\": 64, " + json + "}");
        const fs::path bad = write("bad.json", text);
        const RunResult r = runPenumbra("render " + bad.string() + " --no-display -o " + out.string());
        EXPECT_NE(r.exitCode, 0) << json;
        EXPECT_TRUE(contains(r, "penumbra: error: ")) << json << ": " << r.output;
        EXPECT_TRUE(contains(r, message)) << json << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << json;
    }
}

TEST(AdaptiveConvergence, AdaptiveRunsAreComparedAtEqualError) {
    Scene scene = testing::makeSmallBoxScene(24, 20, 16);
    ConvergenceOptions options;
    options.rungs = {16, 32, 64};
    options.samplers = {SamplerKind::Stratified};
    options.referenceSpp = 1024;
    options.adaptive = true;
    const ConvergenceReport report = runConvergence(scene, options);
    ASSERT_EQ(report.studies.size(), 1u);
    const SamplerStudy& study = report.studies.front();
    ASSERT_TRUE(study.adaptive);
    ASSERT_EQ(study.adaptive->runs.size(), 3u);  // one per rung from --min-spp (16) on
    for (size_t i = 0; i < 3; ++i) {
        const AdaptiveRun& run = study.adaptive->runs[i];
        EXPECT_EQ(run.rung, options.rungs[i]);
        EXPECT_GT(run.threshold, 0.0f);
        EXPECT_EQ(run.maxSpp, 64u * kAdaptiveMaxSppFactor);
        EXPECT_GE(run.meanSpp, 16.0);
        EXPECT_EQ(run.meanSpp, double(run.samples) / (24 * 20));
        if (i > 0) {
            EXPECT_LT(run.threshold, study.adaptive->runs[i - 1].threshold);  // more samples, less error
        }
    }
    ASSERT_EQ(study.adaptive->equalError.size(), 3u);
    for (const EqualErrorPoint& p : study.adaptive->equalError) {
        EXPECT_EQ(p.fixedSamples, double(p.spp) * 24 * 20);
        // Where the adaptive runs reach the rung's error, they do with samples between their extremes.
        if (std::isfinite(p.adaptiveSamples)) {
            EXPECT_GT(p.adaptiveSamples, 0.0);
            EXPECT_GT(p.adaptiveSeconds, 0.0);
        }
    }
}

// With the absolute criterion, each adaptive run's threshold is the RMSE its fixed rung reached.
TEST(AdaptiveConvergence, AbsoluteRunsTargetTheRungsRmse) {
    Scene scene = testing::makeSmallBoxScene(24, 20, 16);
    ConvergenceOptions options;
    options.rungs = {16, 32};
    options.samplers = {SamplerKind::Stratified};
    options.referenceSpp = 512;
    options.adaptive = true;
    options.adaptiveError = AdaptiveError::Absolute;
    const ConvergenceReport report = runConvergence(scene, options);
    ASSERT_EQ(report.studies.size(), 1u);
    const SamplerStudy& study = report.studies.front();
    ASSERT_TRUE(study.adaptive);
    EXPECT_EQ(study.adaptive->error, AdaptiveError::Absolute);
    ASSERT_EQ(study.adaptive->runs.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const AdaptiveRun& run = study.adaptive->runs[i];
        EXPECT_EQ(run.threshold, float(study.runs.front().rungs[i].rmse)) << run.rung;
        EXPECT_GE(run.meanSpp, 16.0);
        EXPECT_GT(run.rmse, 0.0);
    }
}

TEST_F(AdaptiveCommandLine, ConvergeRefusesAnAdaptiveErrorWithoutAdaptive) {
    const fs::path scene = write("scene.json", kScene);
    for (const auto& [arguments, message] :
         {std::pair<std::string, std::string>{"--adaptive-error absolute",
                                              "--adaptive-error: only with --adaptive"},
          {"--adaptive --adaptive-error sideways", "--adaptive-error: expected relative or absolute"}}) {
        const RunResult r = runPenumbra("converge " + scene.string() + " --spp 16,32 --no-plot -q -o " +
                                        (dir_ / "study").string() + " " + arguments);
        EXPECT_NE(r.exitCode, 0) << arguments;
        EXPECT_TRUE(contains(r, message)) << arguments << ": " << r.output;
    }
}

}  // namespace
}  // namespace penumbra
