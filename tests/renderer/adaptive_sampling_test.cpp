// Adaptive sampling (renderer/adaptive_sampling.h): the film does not depend on threads, passes
// or checkpoints; films record the settings, resume exactly and refuse to merge; a flat region
// stops early while an edge keeps sampling; stopped pixels meet the threshold; the absolute
// criterion stops pixels where their share of the image's RMSE says, and the image meets it.
#include "renderer/adaptive_sampling.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/sampling.h"
#include "film/film_exr.h"
#include "film/film_merge.h"
#include "renderer/render.h"
#include "renderer/render_job.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

const SceneSource kSource{"box.json", "fnv1a64:00000000000000ab"};

// The small box, adaptive: at 0.1 the lit walls stop at the first decisions, the penumbrae and
// the light's edges go on to the end (AdaptiveBox.SamplesGoWhereTheNoiseIs checks it).
Scene adaptiveBox(int spp, float threshold = 0.1f, uint32_t minSamples = 16,
                  AdaptiveError error = AdaptiveError::Relative) {
    Scene scene = testing::makeSmallBoxScene(24, 20, spp);
    scene.film.adaptive = AdaptiveSettings{threshold, minSamples, error};
    return scene;
}

// The absolute criterion on the small box: at an image RMSE of 0.03 and 48 samples, pixels hold 16
// to 48 samples (25 on average).
Scene absoluteBox(int spp, float rmse = 0.03f) { return adaptiveBox(spp, rmse, 16, AdaptiveError::Absolute); }

Film renderFilm(const Scene& scene, RenderOptions options) {
    Film film(scene.film.width, scene.film.height);
    render(scene, options, film);
    return film;
}

// `scene` without adaptive sampling at `spp` samples, another seed: the converged image to measure
// errors against.
Film convergedReference(Scene scene, int spp) {
    scene.film.adaptive.reset();
    scene.film.samplesPerPixel = spp;
    scene.settings.seed = 7;
    return renderFilm(scene, RenderOptions{});
}

std::vector<uint32_t> sampleCounts(const Film& film) {
    std::vector<uint32_t> counts;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) counts.push_back(film.at(x, y).sampleCount);
    return counts;
}

TEST(AdaptiveSchedule, DecisionsAtMinSamplesThenAtGrowingSteps) {
    const AdaptiveSettings settings{0.02f, 16};
    std::vector<uint32_t> points;
    for (uint32_t n = settings.nextDecisionAfter(0); n <= 320; n = settings.nextDecisionAfter(n))
        points.push_back(n);
    const std::vector<uint32_t> expected{16,  24,  32,  40,  48,  56,  64,  72,  80,  88,  96,  104, 112,
                                         120, 128, 144, 160, 176, 192, 208, 224, 240, 256, 288, 320};
    EXPECT_EQ(points, expected);
    // isDecisionPoint names the same counts (a resumed render finds them from the count alone).
    std::vector<uint32_t> named;
    for (uint32_t n = 0; n <= 320; ++n)
        if (settings.isDecisionPoint(n)) named.push_back(n);
    EXPECT_EQ(named, expected);
    // A minimum that is not a multiple of 8: the next decision is the next multiple of the step.
    const AdaptiveSettings odd{0.02f, 5};
    EXPECT_EQ(odd.nextDecisionAfter(0), 5u);
    EXPECT_EQ(odd.nextDecisionAfter(5), 8u);
    EXPECT_FALSE(odd.isDecisionPoint(4));
}

TEST(AdaptiveBox, SamplesGoWhereTheNoiseIs) {
    const Scene scene = adaptiveBox(64);
    const Film film = renderFilm(scene, RenderOptions{});
    const std::vector<uint32_t> counts = sampleCounts(film);
    const auto [least, most] = std::minmax_element(counts.begin(), counts.end());
    EXPECT_LE(*least, 32u);  // the quietest pixels stop at one of the first decisions
    EXPECT_EQ(*most, 64u);
    // Pixels stop only at decision points, or hold every sample.
    for (uint32_t n : counts) EXPECT_TRUE(n == 64 || scene.film.adaptive->isDecisionPoint(n)) << n;
    const auto stoppedEarly = std::count_if(counts.begin(), counts.end(), [](uint32_t n) { return n < 64; });
    EXPECT_GT(stoppedEarly, long(counts.size() / 4));
    EXPECT_LT(stoppedEarly, long(counts.size()));
}

TEST(AdaptiveBox, TheFilmDoesNotDependOnThreadsTilesOrPasses) {
    for (const Scene& scene : {adaptiveBox(48), absoluteBox(48)}) {
        RenderOptions one;
        one.threads = 1;
        const Film reference = renderFilm(scene, one);
        const std::vector<uint32_t> counts = sampleCounts(reference);
        ASSERT_LT(*std::min_element(counts.begin(), counts.end()), 48u) << "no pixel stopped";
        for (int threads : {2, 8})
            for (uint32_t passSize : {0u, 3u, 8u}) {
                RenderOptions options;
                options.threads = threads;
                options.passSize = passSize;
                options.tileSize = threads == 8 ? 5 : 16;
                EXPECT_TRUE(renderFilm(scene, options).identicalTo(reference))
                    << adaptiveErrorName(scene.film.adaptive->error) << ", " << threads
                    << " threads, passes of " << passSize;
            }
    }
}

TEST(AdaptiveBox, NonAdaptiveRendersAreUnchanged) {
    // The same scene without film.adaptive: every pixel holds every sample.
    Scene scene = adaptiveBox(24);
    scene.film.adaptive.reset();
    const Film film = renderFilm(scene, RenderOptions{});
    for (uint32_t n : sampleCounts(film)) EXPECT_EQ(n, 24u);
}

class AdaptiveFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-adaptive-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

RenderOptions upTo(uint32_t end, uint32_t passSize = 0) {
    RenderOptions options;
    options.endSample = end;
    options.passSize = passSize;
    return options;
}

TEST_F(AdaptiveFiles, EveryCheckpointResumesToTheUninterruptedFilm) {
    for (const Scene& scene : {adaptiveBox(48), absoluteBox(48)}) {
        const std::string kind(adaptiveErrorName(scene.film.adaptive->error));
        RenderJob once(scene, kSource, upTo(48));
        once.run();

        // Passes of 4 samples: checkpoints at decision points (16, 24, ...) and between them (20, 28, ...).
        RenderJob job(scene, kSource, upTo(48, 4));
        std::vector<uint32_t> ends;
        const fs::path checkpoint = dir_ / (kind + "-checkpoint.exr");
        auto copyAt = [&](uint32_t end) { return dir_ / (kind + "-at-" + std::to_string(end) + ".exr"); };
        job.checkpointEvery(0.0, checkpoint, [&](uint32_t, uint32_t end) {
            fs::copy_file(checkpoint, copyAt(end));
            ends.push_back(end);
        });
        job.run();
        EXPECT_TRUE(job.film().identicalTo(once.film())) << kind;
        ASSERT_EQ(ends.size(), 11u);  // 4, 8, ..., 44
        for (uint32_t end : ends) {
            RenderJob rest(scene, kSource, upTo(48));
            rest.resumeFrom(copyAt(end));
            rest.run();
            EXPECT_TRUE(rest.film().identicalTo(once.film())) << kind << " resumed at " << end;
            EXPECT_EQ(rest.metadata().adaptive, scene.film.adaptive);
        }
    }
}

TEST_F(AdaptiveFiles, AFinishedRenderContinuesToMoreSamples) {
    // 36 is no decision point: the render to 64 decided at 32 and 40, the resumed one at 40.
    const Scene scene = adaptiveBox(64);
    RenderJob once(scene, kSource, upTo(64));
    once.run();
    for (uint32_t shorter : {36u, 40u}) {
        RenderJob first(scene, kSource, upTo(shorter));
        first.run();
        first.writeFilm(dir_ / "short.exr");
        RenderJob rest(scene, kSource, upTo(64));
        rest.resumeFrom(dir_ / "short.exr");
        const RenderStats stats = rest.run();
        EXPECT_TRUE(rest.film().identicalTo(once.film())) << shorter;
        EXPECT_EQ(stats.endSample, 64u);
    }
}

TEST_F(AdaptiveFiles, TheFileRecordsTheSettingsAndEachPixelsCount) {
    const Scene scene = adaptiveBox(40, 0.0625f, 8);
    RenderJob job(scene, kSource, upTo(40));
    job.run();
    job.writeFilm(dir_ / "adaptive.exr");
    const FilmFile file = readFilmExr(dir_ / "adaptive.exr");
    ASSERT_TRUE(file.metadata.adaptive);
    EXPECT_EQ(*file.metadata.adaptive, (AdaptiveSettings{0.0625f, 8}));
    EXPECT_EQ(file.metadata.firstSample, 0u);
    EXPECT_EQ(file.metadata.endSample, 40u);
    EXPECT_TRUE(file.film.identicalTo(job.film()));

    // A threshold without a short decimal form reads back as the same float.
    Scene odd = adaptiveBox(20, 1.0f / 3.0f, 16);
    RenderJob oddJob(odd, kSource, upTo(20));
    oddJob.run();
    oddJob.writeFilm(dir_ / "odd.exr");
    EXPECT_EQ(readFilmExr(dir_ / "odd.exr").metadata.adaptive, odd.film.adaptive);

    // The absolute criterion is recorded as such (and an RMSE may exceed 1).
    for (const float rmse : {0.01f, 2.5f}) {
        Scene absolute = absoluteBox(20, rmse);
        RenderJob absoluteJob(absolute, kSource, upTo(20));
        absoluteJob.run();
        absoluteJob.writeFilm(dir_ / "absolute.exr");
        EXPECT_EQ(readFilmExr(dir_ / "absolute.exr").metadata.adaptive, absolute.film.adaptive) << rmse;
    }

    Scene fixed = scene;
    fixed.film.adaptive.reset();
    RenderJob fixedJob(fixed, kSource, upTo(8));
    fixedJob.run();
    fixedJob.writeFilm(dir_ / "fixed.exr");
    EXPECT_FALSE(readFilmExr(dir_ / "fixed.exr").metadata.adaptive);
}

TEST_F(AdaptiveFiles, ResumeRefusesOtherSettings) {
    const Scene scene = adaptiveBox(32);
    RenderJob first(scene, kSource, upTo(24));
    first.run();
    first.writeFilm(dir_ / "adaptive.exr");

    Scene otherThreshold = adaptiveBox(32, 0.05f);
    Scene otherMinimum = adaptiveBox(32, 0.1f, 8);
    Scene otherError = adaptiveBox(32, 0.1f, 16, AdaptiveError::Absolute);
    Scene fixed = scene;
    fixed.film.adaptive.reset();
    for (const Scene* other : {&otherThreshold, &otherMinimum, &otherError, &fixed}) {
        RenderJob rest(*other, kSource, upTo(32));
        const InputError e = testing::catchInputError([&] { rest.resumeFrom(dir_ / "adaptive.exr"); });
        EXPECT_CONTAINS(e.what(), "adaptive.exr");
        EXPECT_CONTAINS(e.what(), "adaptive sampling");
    }

    // A film of a fixed render is not continued adaptively either.
    RenderJob fixedFirst(fixed, kSource, upTo(24));
    fixedFirst.run();
    fixedFirst.writeFilm(dir_ / "fixed.exr");
    RenderJob adaptiveRest(scene, kSource, upTo(32));
    const InputError e = testing::catchInputError([&] { adaptiveRest.resumeFrom(dir_ / "fixed.exr"); });
    EXPECT_CONTAINS(e.what(), "no adaptive sampling");
}

TEST_F(AdaptiveFiles, ResumeRefusesCountsNoAdaptiveRenderLeaves) {
    const Scene scene = adaptiveBox(32);
    RenderJob first(scene, kSource, upTo(24));
    first.run();
    FilmFile file{Film(scene.film.width, scene.film.height), first.metadataAt(24, 1.0)};
    file.film.merge(first.film());
    PixelSums pixel = file.film.at(3, 2);
    pixel.sampleCount = 17;  // 17 is no decision point, nor 24
    file.film.set(3, 2, pixel);
    writeExr(file.film, file.metadata, dir_ / "crafted.exr");
    RenderJob rest(scene, kSource, upTo(32));
    const InputError e = testing::catchInputError([&] { rest.resumeFrom(dir_ / "crafted.exr"); });
    EXPECT_CONTAINS(e.what(), "pixel (3, 2) holds 17 samples");
}

TEST_F(AdaptiveFiles, MergeRefusesAdaptiveFilms) {
    const Scene scene = adaptiveBox(24);
    RenderOptions left = upTo(24), right = upTo(24);
    left.crop = PixelWindow{0, 12, 0, 20};
    right.crop = PixelWindow{12, 24, 0, 20};
    RenderJob a(scene, kSource, left), b(scene, kSource, right);
    a.run();
    b.run();
    a.writeFilm(dir_ / "left.exr");
    b.writeFilm(dir_ / "right.exr");
    const InputError e = testing::catchInputError([&] {
        mergeFilmFiles({dir_ / "left.exr", dir_ / "right.exr"});
    });
    EXPECT_CONTAINS(e.what(), "left.exr");
    EXPECT_CONTAINS(e.what(), "adaptive render");
}

// A flat wall lit by a small square light, and the sharp shadow of a plate held close to it.
//
// The wall is the plane z = 0 (Lambert, albedo 0.8); a pinhole camera at z = 2 sees [-1, 1]^2 of
// it on 32x32 pixels (box filter: a pixel's samples lie in its own 1/16 x 1/16 of the wall; row
// j covers y in [1 - (j + 1) / 16, 1 - j / 16]). The light is a 0.5 x 0.5 quad at z = 6 centred
// on (0, 6), facing the wall, sampled by area (strategy "light", one bounce), so that a sample's
// radiance is (albedo / pi) Le A G with G = 36 / r^4 (both cosines are 6 / r), or 0 when the
// plate is in the way. The black plate at z = 0.1 covers y >= kPlateEdge: a wall point y is in
// its shadow when the line to the light's centre crosses z = 0.1 above the plate's edge, that is
// y > (kPlateEdge - 0.1) * 60 / 59 = 0.28125, the centre of row 11; the light's half-width
// 0.25 blurs that by 0.25 / 59 ~ 0.07 pixel either way. The camera sees the plate itself above
// y = kPlateEdge / 0.95 (black on the shadowed wall: no edge).
constexpr float kPlateEdge = 0.28125f * 59.0f / 60.0f + 0.1f;
constexpr float kLightRadiance = 1000.0f, kWallAlbedo = 0.8f;
constexpr int kWallPixels = 32;

Scene shadowEdgeScene(int spp, float threshold) {
    Scene scene;
    scene.film = {kWallPixels, kWallPixels, spp, FilterKind::Box, 0.5f};
    scene.film.adaptive = AdaptiveSettings{threshold, 16};
    scene.camera.lookFrom = {0.0f, 0.0f, 2.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = float(2.0 * std::atan(0.5) * 180.0 / kPi);
    scene.integrator.maxDepth = 1;
    scene.integrator.strategy = LightStrategy::Light;
    scene.materials = {testing::makeLambert(Rgb(kWallAlbedo)), testing::makeLambert(Rgb(0.0f))};
    scene.meshes.push_back(testing::makeQuad({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, 0));  // the wall, facing +z
    scene.meshes.push_back(testing::makeQuad({-3, kPlateEdge, 0.1f}, {6, 0, 0}, {0, 3, 0}, 1));  // the plate
    TriangleMesh light = testing::makeQuad({-0.25f, 5.75f, 6.0f}, {0, 0.5f, 0}, {0.5f, 0, 0}, 1);  // faces -z
    light.emission.radiance = Rgb(kLightRadiance);
    scene.meshes.push_back(light);
    return scene;
}

// The smallest and largest radiance a sample of pixel (x, y) of the lit wall can have: G over
// the pixel's patch of wall and the light square.
std::pair<double, double> litSampleBounds(int x, int y) {
    const double pixel = 2.0 / kWallPixels;
    const double x0 = -1.0 + x * pixel, x1 = x0 + pixel, y1 = 1.0 - y * pixel, y0 = y1 - pixel;
    const double dxMin = std::max({0.0, x0 - 0.25, -0.25 - x1}),
                 dxMax = std::max(std::abs(x0), std::abs(x1)) + 0.25;
    const double dyMin = 5.75 - y1, dyMax = 6.25 - y0;
    const double r2Min = 36.0 + dxMin * dxMin + dyMin * dyMin, r2Max = 36.0 + dxMax * dxMax + dyMax * dyMax;
    const double scale = kWallAlbedo / kPi * kLightRadiance * 0.25 * 36.0;
    return {scale / (r2Max * r2Max), scale / (r2Min * r2Min)};
}

TEST(AdaptiveShadowEdge, AFlatRegionStopsEarlyAndTheEdgeKeepsSampling) {
    constexpr int kSpp = 256;
    constexpr float kThreshold = 0.03f;
    const Scene scene = shadowEdgeScene(kSpp, kThreshold);
    const AdaptiveSettings& adaptive = *scene.film.adaptive;
    const Film film = renderFilm(scene, RenderOptions{});
    constexpr int kEdgeRow = 11;
    ASSERT_GT(film.at(16, kEdgeRow + 3).mean().r, 0.3f);  // lit below the edge
    ASSERT_EQ(film.at(16, kEdgeRow - 3).mean().r, 0.0f);  // shadow (and the plate) above

    // Flat, lit: a sample's radiance lies in [a, b] (litSampleBounds), so the variance of the mean
    // that the film estimates from n samples is at most ((b - a) / 2)^2 / (n - 1) (Popoviciu's
    // bound on the biased sample variance, over n - 1), and the mean is at least a: the
    // relative error is at most (b - a) / 2 / sqrt(n - 1) / (a + floor). A pixel stops at the
    // first decision point where that holds for its whole 3x3 neighbourhood (rows from 13 on:
    // row 12 borders the edge). Flat, shadowed: every sample is 0, the error 0; the pixel stops
    // at the first decision unless it borders the edge (row 10 does).
    auto boundStop = [&](double a, double b) {
        for (uint32_t n = adaptive.minSamples; n < kSpp; n = adaptive.nextDecisionAfter(n))
            if ((b - a) / 2.0 / std::sqrt(double(n - 1)) / (a + kAdaptiveErrorFloor) < kThreshold) return n;
        return uint32_t(kSpp);
    };
    for (int y = 0; y < kWallPixels; ++y)
        for (int x = 0; x < kWallPixels; ++x) {
            const uint32_t count = film.at(x, y).sampleCount;
            if (y <= kEdgeRow - 2) {
                EXPECT_EQ(count, adaptive.minSamples) << "shadowed pixel " << x << ", " << y;
            } else if (y >= kEdgeRow + 2) {
                uint32_t bound = 0;
                for (int ny = std::max(kEdgeRow + 2, y - 1); ny <= std::min(kWallPixels - 1, y + 1); ++ny)
                    for (int nx = std::max(0, x - 1); nx <= std::min(kWallPixels - 1, x + 1); ++nx) {
                        const auto [a, b] = litSampleBounds(nx, ny);
                        bound = std::max(bound, boundStop(a, b));
                    }
                EXPECT_LE(count, bound) << "lit pixel " << x << ", " << y;
                EXPECT_LT(count, uint32_t(kSpp / 2)) << "lit pixel " << x << ", " << y;
            }
        }

    // The edge: row 11 is lit over a fraction p = 0.5 +- 0.07 of its patch (the penumbra), and
    // its samples, stratified in each pixel dimension, find a fraction p' within 2/n ~ 0.1 of it
    // (n >= 16): p' in [0.33, 0.67]. Its samples are 0 or at least a, so the variance of their
    // mean m is at least m^2 (1 - p') / p' / (n - 1), and m >= p' a: the relative error is at
    // least sqrt((1 - p') / p' / (n - 1)) p' a / (p' a + floor), over 0.03 for n - 1 < 255 on
    // every pixel of the row. So no pixel of the edge, nor any next to it, stops before 256.
    for (int x = 0; x < kWallPixels; ++x) {
        const double a = litSampleBounds(x, kEdgeRow).first, p = 0.33;
        const double lowest =
            std::sqrt((1 - p) / p / double(kSpp - 1)) * p * a / (p * a + kAdaptiveErrorFloor);
        ASSERT_GT(lowest, kThreshold) << "the scene no longer makes the edge's error bound";
        for (int y = kEdgeRow - 1; y <= kEdgeRow + 1; ++y)
            EXPECT_EQ(film.at(x, y).sampleCount, uint32_t(kSpp)) << "edge pixel " << x << ", " << y;
    }
}

TEST(AdaptiveBox, StoppedPixelsMeetTheThreshold) {
    // With independent samples the film's variance estimate is unbiased, so a pixel that stopped
    // with an estimated relative error e < T has an actual squared error against a converged
    // reference of about (e (m + floor))^2. Measured: the mean over stopped pixels of the squared
    // error (less the reference's own variance), in units of (T (m + floor))^2, must be below 1.
    constexpr float kThreshold = 0.1f;
    Scene scene = adaptiveBox(256, kThreshold);
    scene.settings.sampler = SamplerKind::Independent;
    const Film film = renderFilm(scene, RenderOptions{});
    const Film reference = convergedReference(scene, 4096);

    double sum = 0;
    int stopped = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const PixelSums& p = film.at(x, y);
            if (p.sampleCount >= 256) continue;
            ++stopped;
            EXPECT_LT(relativeStandardError(p), kThreshold);
            const Rgb m = p.mean(), r = reference.at(x, y).mean(), rv = reference.at(x, y).varianceOfMean();
            double squared = 0;
            for (int c = 0; c < 3; ++c) squared += (double(m[c]) - r[c]) * (double(m[c]) - r[c]) - rv[c];
            const double scale = kThreshold * ((double(m.r) + m.g + m.b) / 3.0 + kAdaptiveErrorFloor);
            sum += squared / 3.0 / (scale * scale);
        }
    ASSERT_GT(stopped, 100);
    const double meanRatio = sum / stopped;
    std::printf("stopped %d pixels, mean squared error / (T (m + floor))^2 = %.3f\n", stopped, meanRatio);
    EXPECT_LT(meanRatio, 1.0);
}

// A film whose pixels hold 16 samples alternating 2 + d and 2 - d (every channel): the left half
// d = 1, the right half d = 0.01. Their per-sample standard deviation is d sqrt(16 / 15) (the film's
// unbiased variance), so a pixel's sigma / n is d / sqrt(16 * 15) and mean(sigma) over the film is
// 0.505 sqrt(16 / 15).
Film twoNoiseLevels(int width, int height) {
    Film film(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float d = x < width / 2 ? 1.0f : 0.01f;
            for (int i = 0; i < 16; ++i) film.add(x, y, Rgb(i % 2 == 0 ? 2.0f + d : 2.0f - d), 1.0f);
        }
    return film;
}

TEST(AdaptiveAbsolute, APixelStopsWhenItsShareOfTheImagesErrorIsMet) {
    constexpr int kWidth = 12, kHeight = 4;
    const Film film = twoNoiseLevels(kWidth, kHeight);
    const PixelWindow window{0, kWidth, 0, kHeight};
    const double meanSigma = 0.505 * std::sqrt(16.0 / 15.0), noisyPerSample = 1.0 / std::sqrt(16.0 * 15.0);
    // The threshold T at which the limit T^2 / mean(sigma) is `factor` times the noisy half's sigma / n.
    auto threshold = [&](double factor) { return float(std::sqrt(factor * noisyPerSample * meanSigma)); };

    // Just above the noisy half's sigma / n: every pixel is below, and all stop.
    ActivePixels all(film, window, 16);
    EXPECT_EQ(all.stopConverged(film, AdaptiveSettings{threshold(1.01), 16, AdaptiveError::Absolute}), 48u);
    EXPECT_EQ(all.count(), 0u);

    // Just below it: the quiet half is below (its sigma / n is 1% of the noisy half's), and its
    // pixels stop but for the column next to the noisy half (their neighbourhoods reach into it).
    ActivePixels some(film, window, 16);
    EXPECT_EQ(some.stopConverged(film, AdaptiveSettings{threshold(0.99), 16, AdaptiveError::Absolute}), 20u);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) EXPECT_EQ(some.active(x, y), x <= 6) << x << ", " << y;

    // Just above the quiet half's: the same; just below it, nothing stops.
    ActivePixels quiet(film, window, 16);
    EXPECT_EQ(quiet.stopConverged(film, AdaptiveSettings{threshold(0.0101), 16, AdaptiveError::Absolute}),
              20u);
    ActivePixels none(film, window, 16);
    EXPECT_EQ(none.stopConverged(film, AdaptiveSettings{threshold(0.0099), 16, AdaptiveError::Absolute}), 0u);

    // A noiseless image has nothing left to spend on: every pixel stops.
    Film flat(kWidth, kHeight);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            for (int i = 0; i < 16; ++i) flat.add(x, y, Rgb(0.5f), 1.0f);
    ActivePixels still(flat, window, 16);
    EXPECT_EQ(still.stopConverged(flat, AdaptiveSettings{1e-6f, 16, AdaptiveError::Absolute}), 48u);
}

TEST(AdaptiveAbsolute, TheImageMeetsItsRmse) {
    // A pixel stops once sigma_p / n_p < T^2 / mean(sigma), so its squared error, about
    // sigma_p^2 / n_p, is below sigma_p T^2 / mean(sigma); over the image, below T^2. With
    // independent samples the film's variance estimate is unbiased; the image's mean squared error
    // against a converged reference (less the reference's own variance), in units of T^2, must be
    // below 1, provided no pixel was held back by the most samples a pixel may take (checked).
    constexpr float kRmse = 0.05f;  // pixels from 16 to a few hundred samples
    constexpr int kMostSamples = 4096;
    Scene scene = absoluteBox(kMostSamples, kRmse);
    scene.settings.sampler = SamplerKind::Independent;
    const Film film = renderFilm(scene, RenderOptions{});
    const Film reference = convergedReference(scene, 8192);

    double squared = 0.0;
    uint32_t least = UINT32_MAX, most = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const PixelSums& p = film.at(x, y);
            least = std::min(least, p.sampleCount);
            most = std::max(most, p.sampleCount);
            const Rgb m = p.mean(), r = reference.at(x, y).mean(), rv = reference.at(x, y).varianceOfMean();
            for (int c = 0; c < 3; ++c) squared += (double(m[c]) - r[c]) * (double(m[c]) - r[c]) - rv[c];
        }
    const double mse = squared / (3.0 * film.width() * film.height());
    std::printf("samples per pixel %u to %u; image RMSE %.5f against a target of %.5f\n", least, most,
                std::sqrt(std::max(mse, 0.0)), kRmse);
    ASSERT_LT(most, uint32_t(kMostSamples)) << "a pixel was held back by the most samples";
    ASSERT_LT(least, most) << "the samples did not follow the noise";
    EXPECT_LT(mse / (double(kRmse) * kRmse), 1.0);
}

TEST(AdaptiveJob, RefusesALaterSampleRange) {
    const Scene scene = adaptiveBox(32);
    RenderOptions options = upTo(32);
    options.firstSample = 8;
    const InputError e = testing::catchInputError([&] { RenderJob job(scene, kSource, options); });
    EXPECT_CONTAINS(e.what(), "sample 0");
}

}  // namespace
}  // namespace penumbra
