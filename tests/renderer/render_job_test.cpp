// A render job (renderer/render_job.h): a film resumed from its file, or checkpointed between
// passes, ends bit-identical to one uninterrupted render, and the file says which samples it holds.
#include "renderer/render_job.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "film/film_exr.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class RenderJobFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-render-job-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

const SceneSource kSource{"box.json", "fnv1a64:00000000000000ab"};

RenderOptions samples(uint32_t first, uint32_t end, uint32_t passSize = 0) {
    RenderOptions options;
    options.firstSample = first;
    options.endSample = end;
    options.passSize = passSize;
    return options;
}

TEST_F(RenderJobFiles, AResumedFilmEndsAsOneRender) {
    const Scene scene = testing::makeSmallBoxScene(12, 10, 8);
    RenderJob once(scene, kSource, samples(0, 8));
    once.run();

    RenderJob first(scene, kSource, samples(0, 3));
    first.run();
    first.writeFilm(dir_ / "part.exr");
    RenderJob rest(scene, kSource, samples(0, 8));
    rest.resumeFrom(dir_ / "part.exr");
    EXPECT_TRUE(rest.resumed());
    const RenderStats stats = rest.run();

    EXPECT_EQ(stats.samples, uint64_t(12 * 10 * 5));  // only samples [3, 8) were rendered again
    EXPECT_TRUE(rest.film().identicalTo(once.film()));
    const RenderMetadata m = rest.metadata();
    EXPECT_EQ(m.firstSample, 0u);
    EXPECT_EQ(m.endSample, 8u);
    EXPECT_EQ(m.samplesPerPixel, 8);
    EXPECT_EQ(m.sceneHash, kSource.hash);
    EXPECT_EQ(m.accelerator, "embree");
    EXPECT_EQ(m.sampler, std::string(samplerKindName(scene.settings.sampler)));
}

TEST_F(RenderJobFiles, AFilmOfAnotherSeedIsNotContinued) {
    const Scene scene = testing::makeSmallBoxScene(12, 10, 8);
    RenderJob first(scene, kSource, samples(0, 3));
    first.run();
    first.writeFilm(dir_ / "part.exr");

    Scene reseeded = scene;
    reseeded.settings.seed += 1;
    RenderJob rest(reseeded, kSource, samples(0, 8));
    const InputError e = testing::catchInputError([&] { rest.resumeFrom(dir_ / "part.exr"); });
    EXPECT_CONTAINS(e.what(), "part.exr");
    EXPECT_CONTAINS(e.what(), "seed");
    EXPECT_FALSE(rest.resumed());
}

TEST_F(RenderJobFiles, CheckpointsHoldEachPassAndResumeToTheSameFilm) {
    const Scene scene = testing::makeSmallBoxScene(12, 10, 8);
    RenderJob once(scene, kSource, samples(0, 8));
    once.run();

    RenderJob job(scene, kSource, samples(0, 8, 2));
    std::vector<std::pair<uint32_t, uint32_t>> written;
    std::vector<RenderMetadata> onDisk;
    job.checkpointEvery(0.0, dir_ / "checkpoint.exr", [&](uint32_t first, uint32_t end) {
        written.emplace_back(first, end);
        onDisk.push_back(readFilmExr(dir_ / "checkpoint.exr").metadata);
    });
    job.run();
    // After every pass but the last (the caller writes the finished film).
    const std::vector<std::pair<uint32_t, uint32_t>> expected{{0, 2}, {0, 4}, {0, 6}};
    EXPECT_EQ(written, expected);
    ASSERT_EQ(onDisk.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(onDisk[i].firstSample, expected[i].first);
        EXPECT_EQ(onDisk[i].endSample, expected[i].second);
    }
    EXPECT_TRUE(job.film().identicalTo(once.film()));

    // The last checkpoint ([0, 6)) continues to the same film.
    RenderJob rest(scene, kSource, samples(0, 8));
    rest.resumeFrom(dir_ / "checkpoint.exr");
    rest.run();
    EXPECT_TRUE(rest.film().identicalTo(once.film()));
}

TEST(RenderJob, RefusesANegativeCheckpointInterval) {
    const Scene scene = testing::makeSmallBoxScene(4, 4, 1);
    RenderJob job(scene, kSource, samples(0, 1));
    const InputError e = testing::catchInputError([&] { job.checkpointEvery(-1.0, "x.exr"); });
    EXPECT_CONTAINS(e.what(), "--checkpoint");
}

}  // namespace
}  // namespace penumbra
