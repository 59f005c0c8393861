// Sampling warps against closed-form moments and integrals, plus a chi-square test of the cosine
// hemisphere against its pdf. Inputs are iid uniform numbers from a fixed seed; see
// test_statistics.h for how the 5-sigma tolerances follow from the analytic variances given
// next to each check.
#include "core/sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::Mean;
using test::UniformRng;
using test::withinSigmas;

constexpr int kSamples = 1 << 20;
constexpr double kPiD = std::numbers::pi;

// ---- the chi-square helper itself ---------------------------------------------------------------

TEST(ChiSquareHelper, MatchesReferenceValues) {
    // References from mpmath's regularized upper incomplete gamma function.
    EXPECT_NEAR(test::chiSquarePValue(3.841458820694124, 1), 0.05, 1e-9);
    EXPECT_NEAR(test::chiSquarePValue(18.307038053275146, 10), 0.05, 1e-9);
    EXPECT_NEAR(test::chiSquarePValue(200.0, 199), 0.466745743501378, 1e-9);
    EXPECT_NEAR(test::chiSquarePValue(150.0, 199), 0.996077197317625, 1e-9);
    EXPECT_NEAR(test::chiSquarePValue(260.0, 199), 0.00237096016475193, 1e-11);
    EXPECT_EQ(test::chiSquarePValue(0.0, 5), 1.0);
    // Counts far from expectation are rejected; a sample where none can be gives p = 0.
    EXPECT_LT(test::chiSquareTest({100, 300}, {200, 200}).pValue, 1e-9);
    EXPECT_GT(test::chiSquareTest({195, 205}, {200, 200}).pValue, 0.5);
    EXPECT_EQ(test::chiSquareTest({1, 10, 10}, {0, 10.5, 10.5}).pValue, 0.0);
}

// ---- cosine-weighted hemisphere ---------------------------------------------------------------

TEST(Sampling, CosineHemisphereMomentsAndPdf) {
    UniformRng rng(11);
    Mean cosTheta;
    for (int i = 0; i < kSamples; ++i) {
        const Vec3f w = sampleCosineHemisphere(rng.next2D());
        ASSERT_GE(w.z, 0.0f);
        ASSERT_NEAR(length(w), 1.0f, 1e-6f);
        cosTheta.add(w.z);
    }
    // E[cos] = int cos * (cos / pi) dw = 2/3; E[cos^2] = 1/2, so Var = 1/2 - 4/9 = 1/18.
    EXPECT_TRUE(withinSigmas(cosTheta.value(), 2.0 / 3.0, cosTheta.standardError(1.0 / 18.0)));

    // The pdf integrates to 1 over the sphere: estimate with uniform-sphere samples,
    // f = pdf(w) / (1 / 4pi) = 4 max(z, 0); E[f] = 1, E[f^2] = 16 E[z^2; z > 0] = 16/6,
    // so Var = 8/3 - 1 = 5/3.
    Mean integral;
    for (int i = 0; i < kSamples; ++i) {
        const Vec3f w = sampleUniformSphere(rng.next2D());
        integral.add(cosineHemispherePdf(w.z) / uniformSpherePdf());
    }
    EXPECT_TRUE(withinSigmas(integral.value(), 1.0, integral.standardError(5.0 / 3.0)));
    EXPECT_EQ(cosineHemispherePdf(-0.5f), 0.0f);
    EXPECT_FLOAT_EQ(cosineHemispherePdf(1.0f), 1.0f / kPi);
}

// Pearson's chi-square on a (theta, phi) grid; the expected count of cell
// [t0, t1] x [p0, p1] is n * int cos(t) sin(t) / pi dt dp = n * (p1 - p0) / (2 pi) * (sin^2 t1 - sin^2 t0).
TEST(Sampling, CosineHemisphereChiSquare) {
    constexpr int thetaBins = 16, phiBins = 32;
    constexpr int runs = 4;  // independent sample sets, Sidak-corrected to an overall alpha of 1e-3
    const double alpha = test::sidakAlpha(1e-3, runs);

    std::vector<double> expected(thetaBins * phiBins);
    for (int t = 0; t < thetaBins; ++t) {
        const double s0 = std::sin(0.5 * kPiD * t / thetaBins),
                     s1 = std::sin(0.5 * kPiD * (t + 1) / thetaBins);
        for (int p = 0; p < phiBins; ++p)
            expected[t * phiBins + p] = double(kSamples) / phiBins * (s1 * s1 - s0 * s0);
    }

    for (int run = 0; run < runs; ++run) {
        UniformRng rng(1000 + run);
        std::vector<double> observed(expected.size(), 0.0);
        for (int i = 0; i < kSamples; ++i) {
            const Vec3f w = sampleCosineHemisphere(rng.next2D());
            const double theta = std::acos(std::clamp(double(w.z), -1.0, 1.0));
            double phi = std::atan2(double(w.y), double(w.x));
            if (phi < 0) phi += 2 * kPiD;
            const int t = std::min(thetaBins - 1, int(theta / (0.5 * kPiD) * thetaBins));
            const int p = std::min(phiBins - 1, int(phi / (2 * kPiD) * phiBins));
            observed[t * phiBins + p] += 1;
        }
        const auto result = test::chiSquareTest(observed, expected);
        EXPECT_GT(result.pValue, alpha) << "run " << run << ": " << result.describe();
    }
}

// ---- uniform sphere ---------------------------------------------------------------------------

TEST(Sampling, UniformSphereMoments) {
    UniformRng rng(12);
    Mean z, z2, x, y, x2;
    for (int i = 0; i < kSamples; ++i) {
        const Vec3f w = sampleUniformSphere(rng.next2D());
        ASSERT_NEAR(length(w), 1.0f, 1e-6f);
        z.add(w.z), z2.add(w.z * w.z), x.add(w.x), y.add(w.y), x2.add(w.x * w.x);
    }
    // Each coordinate is uniform on [-1, 1] (Archimedes): E = 0, Var = 1/3; E[c^2] = 1/3 with
    // Var = E[c^4] - 1/9 = 1/5 - 1/9 = 4/45.
    EXPECT_TRUE(withinSigmas(z.value(), 0.0, z.standardError(1.0 / 3.0)));
    EXPECT_TRUE(withinSigmas(x.value(), 0.0, x.standardError(1.0 / 3.0)));
    EXPECT_TRUE(withinSigmas(y.value(), 0.0, y.standardError(1.0 / 3.0)));
    EXPECT_TRUE(withinSigmas(z2.value(), 1.0 / 3.0, z2.standardError(4.0 / 45.0)));
    EXPECT_TRUE(withinSigmas(x2.value(), 1.0 / 3.0, x2.standardError(4.0 / 45.0)));
    EXPECT_FLOAT_EQ(uniformSpherePdf(), float(1.0 / (4.0 * kPiD)));
}

// ---- concentric disk --------------------------------------------------------------------------

TEST(Sampling, ConcentricDiskIsUniform) {
    UniformRng rng(13);
    Mean r2, inner, x, y, quadrant, wedge;
    for (int i = 0; i < kSamples; ++i) {
        const Vec2f d = sampleUniformDiskConcentric(rng.next2D());
        const double rr = double(d.x) * d.x + double(d.y) * d.y;
        ASSERT_LE(rr, 1.0 + 1e-6);
        r2.add(rr);
        inner.add(rr < 0.25 ? 1.0 : 0.0);
        x.add(d.x), y.add(d.y);
        quadrant.add(d.x > 0 && d.y > 0 ? 1.0 : 0.0);
        const double phi = std::atan2(double(d.y), double(d.x));
        wedge.add(phi >= 0 && phi < kPiD / 3 ? 1.0 : 0.0);
    }
    // Uniform on the disk: r^2 is uniform on [0, 1] (E = 1/2, Var = 1/12); the sub-disk of radius
    // 1/2 holds a quarter of the area (Bernoulli, Var = p (1 - p)); E[x] = 0 with Var = E[x^2] = 1/4.
    EXPECT_TRUE(withinSigmas(r2.value(), 0.5, r2.standardError(1.0 / 12.0)));
    EXPECT_TRUE(withinSigmas(inner.value(), 0.25, inner.standardError(0.25 * 0.75)));
    EXPECT_TRUE(withinSigmas(x.value(), 0.0, x.standardError(0.25)));
    EXPECT_TRUE(withinSigmas(y.value(), 0.0, y.standardError(0.25)));
    EXPECT_TRUE(withinSigmas(quadrant.value(), 0.25, quadrant.standardError(0.25 * 0.75)));
    EXPECT_TRUE(withinSigmas(wedge.value(), 1.0 / 6.0, wedge.standardError(1.0 / 6.0 * 5.0 / 6.0)));

    // Chi-square on a polar grid of equal-area cells: r^2 in 8 equal bins times phi in 32 equal
    // bins (catches distortions of the angle within an octant, which the moments above miss).
    constexpr int radialBins = 8, angularBins = 32;
    std::vector<double> observed(radialBins * angularBins, 0.0);
    for (int i = 0; i < kSamples; ++i) {
        const Vec2f d = sampleUniformDiskConcentric(rng.next2D());
        const double rr = double(d.x) * d.x + double(d.y) * d.y;
        double phi = std::atan2(double(d.y), double(d.x));
        if (phi < 0) phi += 2 * kPiD;
        const int r = std::min(radialBins - 1, int(rr * radialBins));
        const int a = std::min(angularBins - 1, int(phi / (2 * kPiD) * angularBins));
        observed[r * angularBins + a] += 1;
    }
    const auto chi2 = test::chiSquareTest(
        observed, std::vector<double>(observed.size(), double(kSamples) / observed.size()));
    EXPECT_GT(chi2.pValue, 1e-3) << chi2.describe();

    // Fixed points of the map: the centre, and square edges onto the circle.
    const Vec2f centre = sampleUniformDiskConcentric({0.5f, 0.5f});
    EXPECT_EQ(centre.x, 0.0f);
    EXPECT_EQ(centre.y, 0.0f);
    const Vec2f right = sampleUniformDiskConcentric({1.0f, 0.5f});
    EXPECT_NEAR(right.x, 1.0f, 1e-6f);
    EXPECT_NEAR(right.y, 0.0f, 1e-6f);
    const Vec2f corner = sampleUniformDiskConcentric({1.0f, 1.0f});
    EXPECT_NEAR(corner.x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(corner.y, std::sqrt(0.5f), 1e-6f);
}

// ---- uniform cone -----------------------------------------------------------------------------

TEST(Sampling, UniformConeStaysInsideWithTheRightMean) {
    for (float cosMax : {0.999f, 0.9f, 0.5f, 0.0f, -0.5f}) {
        SCOPED_TRACE(::testing::Message() << "cosThetaMax = " << cosMax);
        UniformRng rng(14);
        Mean cosTheta, x;
        for (int i = 0; i < kSamples; ++i) {
            const Vec3f w = sampleUniformCone(rng.next2D(), cosMax);
            ASSERT_GE(w.z, cosMax - 1e-6f);
            ASSERT_NEAR(length(w), 1.0f, 1e-6f);
            cosTheta.add(w.z), x.add(w.x);
        }
        // cos(theta) is uniform on [cosMax, 1]: E = (1 + cosMax) / 2, Var = (1 - cosMax)^2 / 12.
        const double width = 1.0 - cosMax;
        EXPECT_TRUE(withinSigmas(cosTheta.value(), (1.0 + cosMax) / 2.0,
                                 cosTheta.standardError(width * width / 12.0)));
        // E[x] = 0; Var = E[sin^2] / 2 <= 1/2 is a safe bound.
        EXPECT_TRUE(withinSigmas(x.value(), 0.0, x.standardError(0.5)));

        // The pdf integrates to 1 over the cone. With uniform-sphere samples the estimator
        // f = 4pi * pdf * [z > cosMax] equals 2 / (1 - cosMax) with probability (1 - cosMax) / 2,
        // so E = 1 and Var = 2 / (1 - cosMax) - 1.
        Mean integral;
        for (int i = 0; i < kSamples; ++i) {
            const Vec3f w = sampleUniformSphere(rng.next2D());
            integral.add(w.z > cosMax ? double(uniformConePdf(cosMax)) / uniformSpherePdf() : 0.0);
        }
        EXPECT_TRUE(withinSigmas(integral.value(), 1.0, integral.standardError(2.0 / width - 1.0)));
    }
}

// ---- uniform triangle -------------------------------------------------------------------------

TEST(Sampling, UniformTriangleBarycentrics) {
    UniformRng rng(15);
    Mean b0, b1, b2, product, corner;
    for (int i = 0; i < kSamples; ++i) {
        const Vec2f b = sampleUniformTriangle(rng.next2D());
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-7f);
        b0.add(b.x), b1.add(b.y), b2.add(1.0 - b.x - b.y);
        product.add(double(b.x) * b.y);
        corner.add(b.x > 0.5f ? 1.0 : 0.0);
    }
    // Uniform barycentrics are Dirichlet(1, 1, 1): each is Beta(1, 2) with mean 1/3 and
    // Var = 2 / (9 * 4) = 1/18; E[b0 b1] = 1/12 with E[b0^2 b1^2] = 2! 2! 2! / 6! = 1/90, so
    // Var = 1/90 - 1/144 = 1/240; b0 > 1/2 is a corner triangle of a quarter of the area.
    EXPECT_TRUE(withinSigmas(b0.value(), 1.0 / 3.0, b0.standardError(1.0 / 18.0)));
    EXPECT_TRUE(withinSigmas(b1.value(), 1.0 / 3.0, b1.standardError(1.0 / 18.0)));
    EXPECT_TRUE(withinSigmas(b2.value(), 1.0 / 3.0, b2.standardError(1.0 / 18.0)));
    EXPECT_TRUE(withinSigmas(product.value(), 1.0 / 12.0, product.standardError(1.0 / 240.0)));
    EXPECT_TRUE(withinSigmas(corner.value(), 0.25, corner.standardError(0.25 * 0.75)));
}

// ---- tent -------------------------------------------------------------------------------------

// CDF of the tent of radius r, density (r - |x|) / r^2.
double tentCdf(double x, double r) {
    if (x < 0) return (x + r) * (x + r) / (2 * r * r);
    return 1.0 - (r - x) * (r - x) / (2 * r * r);
}

TEST(Sampling, TentInvertsItsCdf) {
    for (float radius : {0.5f, 1.0f, 1.5f, 2.0f}) {
        SCOPED_TRACE(::testing::Message() << "radius = " << radius);
        float previous = -radius;
        for (int k = 0; k < 4096; ++k) {
            const float u = float(k) / 4096.0f;
            const float x = sampleTent(u, radius);
            ASSERT_NEAR(tentCdf(x, radius), u, 2e-6) << "u = " << u;
            ASSERT_GE(x, previous) << "not monotonic at u = " << u;
            previous = x;
        }
        EXPECT_FLOAT_EQ(sampleTent(0.0f, radius), -radius);
        EXPECT_FLOAT_EQ(sampleTent(0.5f, radius), 0.0f);

        UniformRng rng(16);
        Mean x, x2;
        for (int i = 0; i < kSamples; ++i) {
            const float v = sampleTent(rng.next(), radius);
            ASSERT_LE(std::abs(v), radius);
            x.add(v), x2.add(double(v) * v);
        }
        // E[x] = 0 and Var = E[x^2] = r^2 / 6; E[x^4] = r^4 / 15, so Var(x^2) = r^4 (1/15 - 1/36)
        // = 7 r^4 / 180.
        const double r2 = double(radius) * radius;
        EXPECT_TRUE(withinSigmas(x.value(), 0.0, x.standardError(r2 / 6.0)));
        EXPECT_TRUE(withinSigmas(x2.value(), r2 / 6.0, x2.standardError(7.0 * r2 * r2 / 180.0)));
    }
}

// ---- power heuristic --------------------------------------------------------------------------

TEST(Sampling, PowerHeuristicWeightsSumToOne) {
    UniformRng rng(17);
    for (int i = 0; i < 100000; ++i) {
        // Log-uniform pdfs over 30 decades, the range a renderer meets in practice.
        const float a = std::pow(10.0f, 30.0f * rng.next() - 15.0f);
        const float b = std::pow(10.0f, 30.0f * rng.next() - 15.0f);
        const float wa = powerHeuristic(a, b), wb = powerHeuristic(b, a);
        ASSERT_NEAR(wa + wb, 1.0f, 1e-6f) << a << " " << b;
        const double exact = double(a) * a / (double(a) * a + double(b) * b);
        ASSERT_NEAR(wa, exact, 1e-6) << a << " " << b;
    }
    EXPECT_FLOAT_EQ(powerHeuristic(1, 1), 0.5f);
    EXPECT_FLOAT_EQ(powerHeuristic(3, 1), 0.9f);
    EXPECT_EQ(powerHeuristic(2, 0), 1.0f);
    EXPECT_EQ(powerHeuristic(0, 2), 0.0f);
    EXPECT_EQ(powerHeuristic(0, 0), 0.0f);
    // A delta strategy (infinite pdf) takes all the weight.
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(powerHeuristic(inf, 5), 1.0f);
    EXPECT_EQ(powerHeuristic(5, inf), 0.0f);
}

// Squares formed in float would overflow for pdfs above ~1.8e19 (both weights 1) and vanish
// below ~1e-19 (both weights 0); the weights must still sum to one there.
TEST(Sampling, PowerHeuristicSurvivesExtremePdfs) {
    EXPECT_NEAR(powerHeuristic(1e20f, 2e20f) + powerHeuristic(2e20f, 1e20f), 1.0f, 1e-6f);
    EXPECT_NEAR(powerHeuristic(1e-25f, 2e-25f) + powerHeuristic(2e-25f, 1e-25f), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace penumbra
