// Tables on the unit square (core/piecewise_linear_2d.h): a bilinear function is reproduced exactly,
// parameters blend their slices linearly, the density integrates to 1, sampling follows it
// (chi-square over a grid of cells whose expected counts are its exact integrals), and invert() undoes
// sample().
#include "core/piecewise_linear_2d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

// A positive, lumpy function to tabulate.
float lumpy(float x, float y, float shift) {
    return 0.05f + std::exp(-30.0f * ((x - 0.3f - shift) * (x - 0.3f - shift) + (y - 0.6f) * (y - 0.6f))) +
           0.5f * x * y;
}

std::vector<float> tabulate(int nx, int ny, float shift) {
    std::vector<float> values;
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x)
            values.push_back(lumpy(float(x) / float(nx - 1), float(y) / float(ny - 1), shift));
    return values;
}

TEST(PiecewiseLinear2D, BilinearFunctionsAreReproducedAndParametersBlendLinearly) {
    // f = a + b x + c y + d x y per slice, two parameters with 3 and 2 nodes.
    const ParameterGrid grid({{0.0f, 1.0f, 3.0f}, {-1.0f, 1.0f}});
    ASSERT_EQ(grid.sliceCount(), 6u);
    const int nx = 5, ny = 4;
    std::vector<float> values;
    const auto f = [](int slice, float x, float y) {
        return float(slice) + (1.0f + float(slice)) * x - 2.0f * y + 0.5f * float(slice) * x * y;
    };
    for (int s = 0; s < 6; ++s)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x)
                values.push_back(f(s, float(x) / float(nx - 1), float(y) / float(ny - 1)));
    const BilinearTable table(values, nx, ny, 1);
    test::UniformRng rng(7);
    for (int i = 0; i < 200; ++i) {
        const Vec2f p = rng.next2D();
        // At a node of both parameters: the slice itself (slice = 2 * first + second).
        const float nodes[2] = {1.0f, 1.0f};
        EXPECT_NEAR(table.eval(p, grid.blend(nodes)), f(3, p.x, p.y), 1e-5f);
        // Halfway between 1 and 3 in the first and 1/4 of the way in the second: the blend of four.
        const float between[2] = {2.0f, -0.5f};
        const float expected = 0.5f * (0.75f * f(2, p.x, p.y) + 0.25f * f(3, p.x, p.y)) +
                               0.5f * (0.75f * f(4, p.x, p.y) + 0.25f * f(5, p.x, p.y));
        EXPECT_NEAR(table.eval(p, grid.blend(between)), expected, 1e-5f);
        // Beyond the nodes: the nearest ones.
        const float outside[2] = {-5.0f, 7.0f};
        EXPECT_NEAR(table.eval(p, grid.blend(outside)), f(1, p.x, p.y), 1e-5f);
    }
    const float notANumber[2] = {NAN, NAN};
    const ParameterBlend blend = grid.blend(notANumber);
    float total = 0.0f;
    for (int k = 0; k < blend.count; ++k) total += blend.weight[size_t(k)];
    EXPECT_FLOAT_EQ(total, 1.0f);
}

TEST(PiecewiseLinear2D, DensityIntegratesToOneAndInvertUndoesSample) {
    const int nx = 9, ny = 7;
    std::vector<float> values = tabulate(nx, ny, 0.0f);
    const std::vector<float> second = tabulate(nx, ny, 0.4f);
    values.insert(values.end(), second.begin(), second.end());
    const ParameterGrid grid({{0.0f, 1.0f}});
    const PiecewiseLinear2D density(values, nx, ny, 2);
    for (const float parameter : {0.0f, 0.3f, 1.0f}) {
        const ParameterBlend blend = grid.blend(&parameter);
        // The midpoint rule on a 700 x 700 grid integrates the bilinear density to within ~1e-5 (its
        // error is second order in the step; 1.4e-7 measured). The tolerances below are float
        // rounding budgets for a few hundred operations over cumulative sums near 1 (measured:
        // 2.7e-7 for the round trip, 1e-6 relative for the densities).
        double integral = 0.0;
        const int n = 700;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) integral += density.pdf({(x + 0.5f) / n, (y + 0.5f) / n}, blend);
        EXPECT_NEAR(integral / (double(n) * n), 1.0, 1e-4) << parameter;
        test::UniformRng rng(11);
        for (int i = 0; i < 2000; ++i) {
            const Vec2f u = rng.next2D();
            const PiecewiseLinear2D::Warped s = density.sample(u, blend);
            EXPECT_NEAR(s.pdf, density.pdf(s.point, blend), 1e-4f * s.pdf);
            const PiecewiseLinear2D::Warped back = density.invert(s.point, blend);
            EXPECT_NEAR(back.point.x, u.x, 2e-4f);
            EXPECT_NEAR(back.point.y, u.y, 2e-4f);
            EXPECT_NEAR(back.pdf, s.pdf, 1e-4f * s.pdf);
        }
    }
}

TEST(PiecewiseLinear2D, SamplesFollowTheBlendedDensity) {
    const int nx = 6, ny = 5;
    std::vector<float> values = tabulate(nx, ny, 0.0f);
    const std::vector<float> second = tabulate(nx, ny, 0.35f);
    values.insert(values.end(), second.begin(), second.end());
    const PiecewiseLinear2D density(values, nx, ny, 2);
    const ParameterGrid grid({{2.0f, 4.0f}});
    const float parameter = 2.7f;
    const ParameterBlend blend = grid.blend(&parameter);
    // Cells of 1/20 x 1/20; the expected mass of each by the 3-point Gauss rule per axis on each
    // quarter of the grid's cells, exact for the bilinear density (degree 1 in each variable).
    const int cells = 20, samples = 400000;
    std::vector<double> observed(cells * cells, 0.0), expected(cells * cells, 0.0);
    static constexpr double kNodes[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
    static constexpr double kWeights[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
    for (int cy = 0; cy < cells; ++cy)
        for (int cx = 0; cx < cells; ++cx) {
            double mass = 0.0;
            // A cell of 1/20 may straddle a grid line (at multiples of 1/5 and 1/4): split it there.
            for (int qy = 0; qy < 4; ++qy)
                for (int qx = 0; qx < 4; ++qx)
                    for (int i = 0; i < 3; ++i)
                        for (int j = 0; j < 3; ++j) {
                            const double x = (cx + (qx + kNodes[i]) / 4.0) / cells,
                                         y = (cy + (qy + kNodes[j]) / 4.0) / cells;
                            mass += kWeights[i] * kWeights[j] * density.pdf({float(x), float(y)}, blend);
                        }
            expected[size_t(cy * cells + cx)] = mass / (16.0 * cells * cells) * samples;
        }
    test::UniformRng rng(0x5eed);
    for (int i = 0; i < samples; ++i) {
        const Vec2f p = density.sample(rng.next2D(), blend).point;
        observed[size_t(std::min(int(p.y * cells), cells - 1) * cells +
                        std::min(int(p.x * cells), cells - 1))] += 1.0;
    }
    const test::ChiSquareResult result = test::chiSquareTest(observed, expected);
    EXPECT_GT(result.pValue, 0.01) << result.describe();
}

}  // namespace
}  // namespace penumbra
