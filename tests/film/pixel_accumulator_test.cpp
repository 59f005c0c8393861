// The 64-bit pre-summing of a pixel's samples must leave the film's sums exactly as direct adds
// would.
#include "film/pixel_accumulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "film/film.h"

namespace penumbra {
namespace {

// Samples of every kind the renderer adds: ordinary radiance, negative and huge AOV values, values
// on both sides of the 64-bit limit (2^8 = 2^56 units), infinities and NaN (adds nothing), misses.
std::vector<std::pair<Rgb, FirstHitAovs>> mixedSamples(int count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float specials[] = {255.99f,
                              256.0f,
                              256.01f,
                              1.0e6f,
                              3.0e7f,
                              std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::quiet_NaN(),
                              -1.0e9f,
                              0x1p-50f};
    std::vector<std::pair<Rgb, FirstHitAovs>> samples;
    for (int i = 0; i < count; ++i) {
        Rgb radiance(unit(rng) * 4.0f, unit(rng), unit(rng) * 20.0f);  // squares up to 400: both paths
        if (i % 7 == 3) radiance.g = specials[(i / 7) % std::size(specials)];
        FirstHitAovs aovs;
        aovs.hit = i % 5 != 0;
        aovs.distance = i % 11 == 0 ? 5.0e5f : unit(rng) * 900.0f;
        aovs.normal = {unit(rng) * 2.0f - 1.0f, -unit(rng), unit(rng)};
        aovs.albedo = Rgb(unit(rng), 1.0f, 0.0f);
        samples.push_back({radiance, aovs});
    }
    return samples;
}

TEST(PixelAccumulator, GivesTheSumsOfDirectAddsBitForBit) {
    // 200 samples: several flushes of kMaxSamples, then a partial one by the destructor.
    for (const float weight : {1.0f, 0.37f, 3.0f}) {
        PixelSums direct;
        Film film(1, 1);
        const auto samples = mixedSamples(200, 7);
        {
            PixelAccumulator accumulator(film, 0, 0);
            for (const auto& [radiance, aovs] : samples) {
                direct.add(radiance, weight, aovs);
                accumulator.add(radiance, weight, aovs);
            }
        }
        EXPECT_EQ(film.at(0, 0).sampleCount, 200u);
        EXPECT_TRUE(film.at(0, 0) == direct) << "weight " << weight;
    }
}

TEST(PixelAccumulator, FlushesAtMostEveryKMaxSamples) {
    // Addends just below the 64-bit limit, kMaxSamples of them per sum, must not overflow: the
    // radiance sum would wrap if a 65th were summed in 64 bits.
    const float nearLimit = std::nextafter(256.0f, 0.0f);  // 2^56 units less one ulp
    PixelSums direct;
    Film film(1, 1);
    {
        PixelAccumulator accumulator(film, 0, 0);
        for (int i = 0; i < 3 * PixelAccumulator::kMaxSamples + 1; ++i) {
            const FirstHitAovs miss;
            direct.add(Rgb(nearLimit), 1.0f, miss);
            accumulator.add(Rgb(nearLimit), 1.0f, miss);
        }
    }
    const PixelSums accumulated = film.at(0, 0);
    EXPECT_TRUE(accumulated == direct);
    // Exact, so compared exactly: nearLimit is (2^24 - 1) 2^-16, one addend (2^24 - 1) 2^32 units,
    // and 193 of them have fewer than 53 significant bits, as a double and as value() returns them.
    EXPECT_EQ(accumulated.radiance[0].value(), (3.0 * PixelAccumulator::kMaxSamples + 1) * nearLimit);
}

TEST(PixelAccumulator, SumsAreAddressedInTheDeclaredOrder) {
    PixelSums p;
    const ExactSum* declared[] = {&p.radiance[0],
                                  &p.radiance[1],
                                  &p.radiance[2],
                                  &p.radianceSquared[0],
                                  &p.radianceSquared[1],
                                  &p.radianceSquared[2],
                                  &p.weight,
                                  &p.albedo[0],
                                  &p.albedo[1],
                                  &p.albedo[2],
                                  &p.normal[0],
                                  &p.normal[1],
                                  &p.normal[2],
                                  &p.depth,
                                  &p.hitWeight};
    ASSERT_EQ(std::size(declared), size_t(PixelSums::kSumCount));
    for (int i = 0; i < PixelSums::kSumCount; ++i) EXPECT_EQ(&p.sum(i), declared[i]) << i;
}

}  // namespace
}  // namespace penumbra
