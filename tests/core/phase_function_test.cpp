// The Henyey-Greenstein phase function (core/henyey_greenstein.h): normalized, its samples
// distributed as it says (chi-square over cos(theta) and the azimuth), and each sample's density
// the function's value, for forward, backward and isotropic g.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/henyey_greenstein.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

// The phase function written out again, independently of the code under test: the density over
// the sphere of cos(theta) between the scattered direction and the incident one (-wo).
double hgDensity(double cosForward, double g) {
    return (1 - g * g) / (4 * M_PI * std::pow(1 + g * g - 2 * g * cosForward, 1.5));
}

// Probability that cos(theta) (from the forward direction -wo) falls in [a, b): Simpson's rule on
// 2 pi hgDensity, 2000 steps a bin (exact to about 1e-12 for |g| <= 0.9 at 40 bins).
double binProbability(double a, double b, double g) {
    const int steps = 2000;
    const double h = (b - a) / steps;
    double sum = hgDensity(a, g) + hgDensity(b, g);
    for (int i = 1; i < steps; ++i) sum += hgDensity(a + i * h, g) * (i % 2 ? 4 : 2);
    return 2 * M_PI * sum * h / 3;
}

const float kGs[] = {-0.7f, 0.0f, 0.3f, 0.9f};

TEST(HenyeyGreenstein, IntegratesToOneOverTheSphere) {
    for (float g : kGs) {
        const HenyeyGreenstein phase{g};
        const Vec3f wo{0.0f, 0.0f, 1.0f};
        // Over cos(theta) in [-1, 1] (the function depends on it alone), Simpson's rule.
        const int steps = 1 << 16;
        const double h = 2.0 / steps;
        auto f = [&](double mu) {
            const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
            return 2 * M_PI * phase.p(wo, {float(s), 0.0f, float(mu)});
        };
        double sum = f(-1) + f(1);
        for (int i = 1; i < steps; ++i) sum += f(-1 + i * h) * (i % 2 ? 4 : 2);
        EXPECT_NEAR(sum * h / 3, 1.0, 1e-4) << "g " << g;
    }
}

TEST(HenyeyGreenstein, SamplesFollowTheDensityAndReportIt) {
    const Vec3f wo = normalize(Vec3f{0.3f, -0.5f, 0.8f});
    const Vec3f forward = -wo;
    // A frame of our own around the forward direction, for the azimuth.
    const Vec3f a = normalize(cross(forward, std::abs(forward.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
    const Vec3f b = cross(forward, a);
    const int muBins = 40, phiBins = 8, n = 1 << 20;
    const double alpha = test::sidakAlpha(1e-6, int(std::size(kGs)));
    for (float g : kGs) {
        const HenyeyGreenstein phase{g};
        test::UniformRng rng(1234);
        std::vector<double> observed(size_t(muBins) * phiBins, 0.0), expected(observed.size());
        for (int i = 0; i < n; ++i) {
            const PhaseSample s = phase.sample(wo, rng.next2D());
            ASSERT_NEAR(length(s.wi), 1.0f, 1e-4f);
            const double mu = std::clamp(double(dot(s.wi, forward)), -1.0, 1.0);
            ASSERT_NEAR(s.pdf, hgDensity(mu, g), 1e-3 * hgDensity(mu, g)) << "g " << g;
            const double phi = std::atan2(double(dot(s.wi, b)), double(dot(s.wi, a))) + M_PI;
            const int muBin = std::min(muBins - 1, int((mu + 1) / 2 * muBins));
            const int phiBin = std::min(phiBins - 1, int(phi / (2 * M_PI) * phiBins));
            observed[size_t(muBin) * phiBins + size_t(phiBin)] += 1;
        }
        for (int m = 0; m < muBins; ++m) {
            const double p = binProbability(-1 + 2.0 * m / muBins, -1 + 2.0 * (m + 1) / muBins, g);
            for (int k = 0; k < phiBins; ++k) expected[size_t(m) * phiBins + size_t(k)] = p * n / phiBins;
        }
        const test::ChiSquareResult result = test::chiSquareTest(observed, expected);
        EXPECT_GT(result.pValue, alpha) << "g " << g << ": chi-square " << result.statistic;
    }
}

}  // namespace
}  // namespace penumbra
