// Statistical helpers shared by the core tests: a deterministic uniform generator, checks of
// Monte Carlo estimates against their standard error, and Pearson's chi-square test.
//
// Tolerances. For n independent samples of f with variance s^2, the sample mean is approximately
// normal (central limit theorem) with standard error sigma = s / sqrt(n). A check passes when the
// estimate lies within 5 sigma of the exact value: a correct warp fails such a check with
// probability 5.7e-7, and because every test uses a fixed seed the outcome is deterministic
// anyway. A bias larger than 5 sigma (about 0.1% of the value with n = 2^20) is detected.
// Variances are the analytic ones, derived next to each check.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

#include "core/vec.h"

namespace penumbra::test {

// Uniform floats in [0, 1) with 24 random bits (never 1, unlike some uniform_real_distribution
// implementations for float).
class UniformRng {
public:
    explicit UniformRng(uint64_t seed) : engine_(seed) {}
    float next() { return float(engine_() >> 40) * 0x1p-24f; }
    Vec2f next2D() {
        const float x = next();
        return {x, next()};
    }

private:
    std::mt19937_64 engine_;
};

// |estimate - exact| <= k * standardError, with a message giving the number of sigmas.
inline ::testing::AssertionResult withinSigmas(double estimate, double exact, double standardError,
                                               double k = 5.0) {
    const double deviation = std::abs(estimate - exact) / standardError;
    if (deviation <= k) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "estimate " << estimate << " vs exact " << exact << " is " << deviation << " standard errors ("
           << standardError << ") away; allowed " << k;
}

// Running mean of a sequence of values.
struct Mean {
    double sum = 0.0;
    uint64_t n = 0;
    void add(double v) { sum += v, ++n; }
    double value() const { return sum / double(n); }
    // Standard error of the mean for a quantity of known variance.
    double standardError(double variance) const { return std::sqrt(variance / double(n)); }
};

// Regularized upper incomplete gamma function Q(a, x) (series for x < a + 1, Lentz's continued
// fraction otherwise; Numerical Recipes 6.2).
inline double regularizedGammaQ(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double logPrefactor = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double ap = a, term = 1.0 / a, sum = term;
        for (int i = 0; i < 100000; ++i) {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-16) break;
        }
        return std::max(0.0, 1.0 - sum * std::exp(logPrefactor));
    }
    constexpr double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-16) break;
    }
    return std::exp(logPrefactor) * h;
}

// P(X >= statistic) for X chi-square distributed with `dof` degrees of freedom.
inline double chiSquarePValue(double statistic, int dof) {
    return regularizedGammaQ(0.5 * dof, 0.5 * statistic);
}

// Significance level of each of `numTests` tests such that the chance that any of them rejects a
// correct null hypothesis is `alpha` (Sidak correction).
inline double sidakAlpha(double alpha, int numTests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / numTests); }

struct ChiSquareResult {
    double statistic = 0.0;
    int dof = 0;
    double pValue = 1.0;
    std::string describe() const {
        std::ostringstream out;
        out << "chi^2 = " << statistic << " with " << dof << " degrees of freedom, p = " << pValue;
        return out.str();
    }
};

// Pearson's chi-square test of observed counts against expected counts. Cells expected to hold
// fewer than 5 samples are pooled (the chi-square approximation needs about 5 per cell); a sample
// in a cell of zero expected count is impossible and gives p = 0.
inline ChiSquareResult chiSquareTest(const std::vector<double>& observed,
                                     const std::vector<double>& expected) {
    std::vector<size_t> order(expected.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });

    ChiSquareResult result;
    double pooledObserved = 0.0, pooledExpected = 0.0;
    int cells = 0;
    for (size_t i : order) {
        if (expected[i] == 0.0) {
            if (observed[i] > 0.0) {
                result.pValue = 0.0;
                return result;
            }
            continue;
        }
        if (expected[i] < 5.0 || (pooledExpected > 0.0 && pooledExpected < 5.0)) {
            // Still filling the pool of small cells (the smallest come first).
            pooledObserved += observed[i];
            pooledExpected += expected[i];
            continue;
        }
        const double diff = observed[i] - expected[i];
        result.statistic += diff * diff / expected[i];
        ++cells;
    }
    if (pooledExpected > 0.0) {
        const double diff = pooledObserved - pooledExpected;
        result.statistic += diff * diff / pooledExpected;
        ++cells;
    }
    result.dof = cells - 1;
    result.pValue = result.dof > 0 ? chiSquarePValue(result.statistic, result.dof) : 1.0;
    return result;
}

}  // namespace penumbra::test
