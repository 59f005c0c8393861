// The film's compact sums (film/film.h, film/high_words.h): each sum's low 64 bits in place and
// its high 64 bits only where it has outgrown them. Sums that wrap their low word many times, up
// and down, must read back as the same 128-bit integers that PixelSums' direct adds give, through
// PixelAccumulator, merges in either order, an EXR round trip and threads adding to the pixels of
// one block of high words at once.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <filesystem>
#include <random>
#include <vector>

#include "film/film.h"
#include "film/film_exr.h"
#include "film/pixel_accumulator.h"

namespace penumbra {
namespace {

// Samples whose sums pass 2^15 (2^63 units) many times: squared radiance up to 900 a sample, and
// through the 64-bit pre-sums (below 2^56 units an addend) as well as directly (above); depth up
// to 5000 and normals of either sign, so sums wrap downwards too.
std::vector<std::pair<Rgb, FirstHitAovs>> wrappingSamples(int count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<std::pair<Rgb, FirstHitAovs>> samples;
    for (int i = 0; i < count; ++i) {
        const Rgb radiance(unit(rng) * 15.0f, 20.0f + unit(rng) * 10.0f, unit(rng));
        FirstHitAovs aovs;
        aovs.hit = i % 9 != 0;
        aovs.distance = 5000.0f * unit(rng);
        aovs.normal = {-1.0f, unit(rng) * 2.0f - 1.0f, 1.0f};
        aovs.albedo = Rgb(unit(rng));
        samples.push_back({radiance, aovs});
    }
    return samples;
}

constexpr int kSamples = 6000;

// The film of `width` x 1 pixels whose pixel x holds samples [first, end) of wrappingSamples(x).
Film filmOf(int width, int first, int end) {
    Film film(width, 1);
    for (int x = 0; x < width; ++x) {
        const auto samples = wrappingSamples(kSamples, uint32_t(x));
        PixelAccumulator pixel(film, x, 0);
        for (int i = first; i < end; ++i) pixel.add(samples[i].first, 1.0f, samples[i].second);
    }
    return film;
}

PixelSums directSums(int x) {
    PixelSums sums;
    for (const auto& [radiance, aovs] : wrappingSamples(kSamples, uint32_t(x)))
        sums.add(radiance, 1.0f, aovs);
    return sums;
}

TEST(FilmSums, SumsPastSixtyFourBitsReadAsTheirFullIntegers) {
    const Film film = filmOf(3, 0, kSamples);
    for (int x = 0; x < 3; ++x) {
        const PixelSums direct = directSums(x);
        // The sums the samples make are beyond 64 bits, positive and negative: what is tested.
        EXPECT_GT(double(direct.radianceSquared[1]), 0x1p18);
        EXPECT_GT(double(direct.depth), 0x1p20);
        EXPECT_LT(double(direct.normal[0]), -0x1p12);
        EXPECT_TRUE(film.at(x, 0) == direct) << "pixel " << x;
    }
    EXPECT_TRUE(film.hasHighWords(PixelSums::kRadianceSquared + 1));
    EXPECT_FALSE(film.hasHighWords(PixelSums::kAlbedo));  // below 2^15 everywhere
}

TEST(FilmSums, AddsOneSampleAtATimeAsPixelSumsDoes) {
    Film film(2, 2);
    for (const auto& [radiance, aovs] : wrappingSamples(kSamples, 0)) film.add(1, 1, radiance, 1.0f, &aovs);
    EXPECT_TRUE(film.at(1, 1) == directSums(0));
    EXPECT_TRUE(film.at(0, 1) == PixelSums{});
}

TEST(FilmSums, MergesOfPartsAreTheWholeInEitherOrder) {
    const Film whole = filmOf(3, 0, kSamples);
    Film a = filmOf(3, 0, 2500), b = filmOf(3, 2500, kSamples);
    Film ab = a, ba = b;
    ab.merge(b);
    ba.merge(a);
    EXPECT_TRUE(ab.identicalTo(whole));
    EXPECT_TRUE(ba.identicalTo(whole));
    EXPECT_FALSE(a.identicalTo(whole));
}

TEST(FilmSums, HighWordsSurviveTheExrRoundTrip) {
    const Film film = filmOf(3, 0, kSamples);
    const auto path =
        std::filesystem::temp_directory_path() / ("film_sums_test_" + std::to_string(getpid()) + ".exr");
    RenderMetadata meta;
    meta.seed = 1;
    meta.firstSample = 0;
    meta.endSample = kSamples;
    writeExr(film, meta, path);
    const FilmFile read = readFilmExr(path);
    std::filesystem::remove(path);
    EXPECT_TRUE(read.film.identicalTo(film));
}

TEST(FilmSums, ThreadsWrappingPixelsOfOneBlockAtOnceGiveTheSerialSums) {
    // 256 pixels, 4 blocks of high words: every pixel wraps, every block is allocated by whichever
    // thread gets there first.
    constexpr int kWidth = 4 * int(HighWords::kBlockPixels), kPerPixel = 800;
    auto fill = [&](Film& film, int x) {
        const auto samples = wrappingSamples(kPerPixel, uint32_t(x));
        PixelAccumulator pixel(film, x, 0);
        for (const auto& [radiance, aovs] : samples) pixel.add(radiance, 1.0f, aovs);
    };
    Film serial(kWidth, 1), parallel(kWidth, 1);
    for (int x = 0; x < kWidth; ++x) fill(serial, x);
    tbb::parallel_for(
        0, kWidth, [&](int x) { fill(parallel, x); }, tbb::simple_partitioner());
    EXPECT_TRUE(serial.hasHighWords(PixelSums::kRadianceSquared + 1));
    EXPECT_TRUE(parallel.identicalTo(serial));
}

}  // namespace
}  // namespace penumbra
