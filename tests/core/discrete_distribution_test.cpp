// DiscreteDistribution: the choice of a light by power.
#include "core/discrete_distribution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

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
    for (float u : {0.0f, 1e-7f, 2.0f / 3.0f, std::nextafter(2.0f / 3.0f, 0.0f), std::nextafter(1.0f, 0.0f)}) {
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

}  // namespace
}  // namespace penumbra
