// DiscreteDistribution: the choice of a light by power.
#include "core/discrete_distribution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/sampler.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

// Chi-square of the chosen items against the weights, for n uniform u. At the fixed seed the
// outcome is deterministic; a correct sampler fails p < 1e-4 with probability 1e-4.
TEST(DiscreteDistribution, ChoosesItemsInProportionToTheirWeights) {
    const std::vector<double> weights = {1.0, 0.0, 3.0, 0.5, 2.5, 1e-3};
    const DiscreteDistribution d(weights);
    ASSERT_EQ(d.size(), weights.size());
    double total = 0.0;
    for (double w : weights) total += w;

    const int n = 1 << 20;
    std::vector<double> observed(weights.size(), 0.0), expected(weights.size());
    test::UniformRng rng(7);
    for (int i = 0; i < n; ++i) observed[d.sample(rng.next())] += 1.0;
    for (size_t i = 0; i < weights.size(); ++i) {
        expected[i] = n * weights[i] / total;
        EXPECT_FLOAT_EQ(d.probability(i), float(weights[i] / total)) << "item " << i;
    }
    const test::ChiSquareResult r = test::chiSquareTest(observed, expected);
    EXPECT_GT(r.pValue, 1e-4) << r.describe();
}

TEST(DiscreteDistribution, NeverChoosesAnItemOfZeroWeight) {
    const DiscreteDistribution d({0.0, 2.0, 0.0, 0.0, 1.0, 0.0});
    // The ends of [0, 1) and the boundaries between the items included.
    for (float u :
         {0.0f, 1e-7f, 2.0f / 3.0f, std::nextafter(2.0f / 3.0f, 0.0f), std::nextafter(1.0f, 0.0f)}) {
        const uint32_t item = d.sample(u);
        EXPECT_TRUE(item == 1 || item == 4) << "u = " << u << " chose " << item;
    }
}

TEST(DiscreteDistribution, ASingleItemIsAlwaysChosenWithProbabilityOne) {
    const DiscreteDistribution d({0.25});
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.probability(0), 1.0f);
    for (float u : {0.0f, 0.5f, std::nextafter(1.0f, 0.0f)}) EXPECT_EQ(d.sample(u), 0u);
}

TEST(DiscreteDistribution, NoPositiveWeightMakesAnEmptyDistribution) {
    EXPECT_TRUE(DiscreteDistribution({0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}).empty());
    EXPECT_TRUE(DiscreteDistribution(std::vector<double>{}).empty());
    EXPECT_FALSE(DiscreteDistribution({0.0, 1.0}).empty());
}

// The remapped value is u's position within the chosen item's interval: the same item as sample(u),
// values in [0, 1), in the order of u, and uniform for uniform u (chi-square per item).
TEST(DiscreteDistribution, RemapsUWithinTheChosenItem) {
    const DiscreteDistribution d({1.0, 0.0, 3.0, 0.5});
    const int n = 1 << 18, bins = 16;
    std::vector<std::vector<double>> observed(4, std::vector<double>(bins, 0.0));
    std::vector<float> previous(4, -1.0f);
    for (int i = 0; i < n; ++i) {
        const float u = (float(i) + 0.5f) / float(n);
        float remapped = u;
        const uint32_t item = d.sampleAndRemap(remapped);
        ASSERT_EQ(item, d.sample(u)) << "u = " << u;
        ASSERT_GE(remapped, 0.0f);
        ASSERT_LT(remapped, 1.0f);
        ASSERT_GE(remapped, previous[item]) << "u = " << u;  // u in order: the item's values in order
        previous[item] = remapped;
        observed[item][std::min(bins - 1, int(remapped * bins))] += 1.0;
    }
    for (uint32_t item : {0u, 2u, 3u}) {
        double count = 0.0;
        for (double o : observed[item]) count += o;
        const test::ChiSquareResult r =
            test::chiSquareTest(observed[item], std::vector<double>(bins, count / bins));
        EXPECT_GT(r.pValue, 1e-4) << "item " << item << ": " << r.describe();
    }
    // The end of [0, 1) stays below 1.
    float last = std::nextafter(1.0f, 0.0f);
    EXPECT_EQ(d.sampleAndRemap(last), 3u);
    EXPECT_LT(last, 1.0f);
    float single = 0.3f;
    EXPECT_EQ(DiscreteDistribution({2.0}).sampleAndRemap(single), 0u);
    EXPECT_EQ(single, 0.3f);
}

// Why the value is reused: the stratified sampler's 64 values of a pixel form a (0, 6, 2)-net, so
// the 2^(6-k) of them that choose an item of probability 2^-k, remapped, form a (0, 6 - k, 2)-net:
// each elementary interval of area 2^(k-6) holds exactly one point, so the point on each light is
// as stratified as its share of the samples allows. (A separate choice value would hand each light
// a random subset of the points instead.)
TEST(DiscreteDistribution, RemappedStratifiedValuesStayStratifiedForEachItem) {
    const DiscreteDistribution d({1.0, 1.0, 2.0});  // probabilities 1/4, 1/4, 1/2
    const int spp = 64;
    for (uint64_t pixel : {0u, 1u, 977u}) {
        std::vector<std::vector<Vec2f>> points(3);
        for (uint32_t i = 0; i < uint32_t(spp); ++i) {
            Vec2f u = PixelSample(SamplerKind::Stratified, 5, pixel, i).get2D(Dim::LightPosition, 1);
            const uint32_t item = d.sampleAndRemap(u.x);
            points[item].push_back(u);
        }
        for (uint32_t item = 0; item < 3; ++item) {
            const int m = int(points[item].size());
            ASSERT_EQ(m, int(d.probability(item) * spp)) << "pixel " << pixel << " item " << item;
            for (int xBits = 0; (1 << xBits) <= m; ++xBits) {
                const int nx = 1 << xBits, ny = m / nx;
                std::vector<int> cells(m, 0);
                for (Vec2f p : points[item])
                    ++cells[std::min(ny - 1, int(p.y * ny)) * nx + std::min(nx - 1, int(p.x * nx))];
                for (int c = 0; c < m; ++c)
                    ASSERT_EQ(cells[c], 1)
                        << "pixel " << pixel << " item " << item << ", " << nx << "x" << ny << " cells";
            }
        }
    }
}

}  // namespace
}  // namespace penumbra
