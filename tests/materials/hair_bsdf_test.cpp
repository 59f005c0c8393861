// The hair BSDF (materials/hair_bsdf.h) against what the model guarantees: without absorption it
// returns all the light it receives (the white furnace: the integral of f |cos| over the sphere is
// 1), its pdf integrates to 1, its samples follow its pdf (chi-square against the pdf integrated
// over cells of the sphere), absorption only takes light away, and the parameterizations by
// melanin and by colour behave as their definitions say.
#include "materials/hair_bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "tests/support/bsdf_test_support.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

// A unit direction of the fiber's frame from sin(theta) (along the fiber, x) and the azimuth phi.
Vec3f fiberDirection(double sinTheta, double phi) {
    const double cosTheta = std::sqrt(std::max(0.0, 1.0 - sinTheta * sinTheta));
    return {float(sinTheta), float(cosTheta * std::cos(phi)), float(cosTheta * std::sin(phi))};
}

// The integral over the sphere of g(wi), by the midpoint rule in (sin(theta), phi), where the solid
// angle is d sin(theta) d phi: `steps` rows of sin(theta), twice as many columns of phi.
template <typename G>
double sphereIntegral(G g, int steps) {
    const double dx = 2.0 / steps, dphi = 2.0 * test::kPiD / (2 * steps);
    double sum = 0.0;
    for (int i = 0; i < steps; ++i)
        for (int j = 0; j < 2 * steps; ++j)
            sum += g(fiberDirection(-1.0 + (i + 0.5) * dx, -test::kPiD + (j + 0.5) * dphi));
    return sum * dx * dphi;
}

struct Setting {
    float betaM, betaN, h;
    Vec3f wo;
};

std::vector<Setting> settings() {
    std::vector<Setting> out;
    const Vec3f wos[] = {normalize(Vec3f{0.3f, 0.8f, 0.5f}), normalize(Vec3f{-0.7f, 0.2f, -0.6f})};
    for (float betaM : {0.2f, 0.5f, 0.9f})
        for (float betaN : {0.2f, 0.5f, 0.9f})
            out.push_back({betaM, betaN, betaM > 0.4f ? -0.5f : 0.3f, wos[out.size() % 2]});
    return out;
}

TEST(HairBsdf, WhiteFurnaceWithoutAbsorption) {
    for (const Setting& s : settings()) {
        HairBsdf hair;
        hair.betaM = s.betaM;
        hair.betaN = s.betaN;
        hair.h = s.h;
        const Vec3f wo = s.wo;
        const double reflected =
            sphereIntegral([&](Vec3f wi) { return double(hair.eval(wo, wi, true).g) * std::abs(wi.z); }, 600);
        // The pdf with absorption, where the lobes' probabilities are no longer their Ap.
        HairBsdf absorbing = hair;
        absorbing.sigmaA = HairBsdf::sigmaAFromConcentration(1.0f, 0.5f);
        const double mass =
            sphereIntegral([&](Vec3f wi) { return double(absorbing.pdf(wo, wi, true)); }, 600);
        std::printf(
            "beta_m %.1f, beta_n %.1f, h %+.1f: integral of f |cos| %.5f, of an absorbing fiber's pdf %.5f\n",
            s.betaM, s.betaN, s.h, reflected, mass);
        // Energy conservation within 1%; the pdf's mass, a density's, within the quadrature's error.
        EXPECT_NEAR(reflected, 1.0, 0.01) << s.betaM << " " << s.betaN;
        EXPECT_NEAR(mass, 1.0, 0.005) << s.betaM << " " << s.betaN;
    }
}

// Absorption by melanin only takes light away, the more the darker; the colour's inversion gives
// less absorption for a lighter colour and none for white.
TEST(HairBsdf, AbsorptionOnlyTakesLightAway) {
    const Vec3f wo = normalize(Vec3f{0.2f, 0.9f, 0.3f});
    double previous = 1.0 + 1e-3;
    for (float eumelanin : {0.0f, 0.3f, 1.3f, 8.0f}) {
        HairBsdf hair;
        hair.sigmaA = HairBsdf::sigmaAFromConcentration(eumelanin, 0.0f);
        const double albedo =
            sphereIntegral([&](Vec3f wi) { return double(hair.eval(wo, wi, true).g) * std::abs(wi.z); }, 300);
        EXPECT_LT(albedo, previous) << eumelanin;
        previous = albedo;
    }
    EXPECT_GT(previous, 0.02);  // the fiber's surface reflection stays
    const Rgb light = HairBsdf::sigmaAFromReflectance(Rgb(0.8f), 0.3f);
    const Rgb dark = HairBsdf::sigmaAFromReflectance(Rgb(0.1f), 0.3f);
    EXPECT_LT(light.r, dark.r);
    EXPECT_EQ(HairBsdf::sigmaAFromReflectance(Rgb(1.0f), 0.3f).g, 0.0f);
    // Pheomelanin absorbs blue most: red hair.
    const Rgb red = HairBsdf::sigmaAFromConcentration(0.0f, 1.0f);
    EXPECT_LT(red.r, red.b);
}

// Samples against the pdf: cells of the sphere about the fiber's axis (the lobes are cones about it),
// their expected counts by adaptive cubature of pdf(), a chi-square test of the counts; each
// sample's pdf is pdf() of its direction and its weight eval() |cos| / pdf.
TEST(HairBsdf, SamplesFollowThePdf) {
    constexpr int kSamples = 1'000'000;
    const std::vector<Setting> all = settings();
    const double alpha = test::sidakAlpha(0.01, int(all.size()));
    for (size_t k = 0; k < all.size(); k += 2) {
        const Setting& s = all[k];
        HairBsdf hair;
        hair.betaM = s.betaM;
        hair.betaN = s.betaN;
        hair.h = s.h;
        hair.sigmaA = HairBsdf::sigmaAFromConcentration(0.5f, 0.2f);
        const Vec3f wo = s.wo;
        test::SphereBinning binning;
        binning.frame = Frame::fromNormal({1.0f, 0.0f, 0.0f});
        binning.thetaBins = 24;
        binning.phiBins = 48;
        const test::CellIntegrals cells = test::integrateOverCells(
            binning, [&](Vec3f wi) { return hair.pdf(wo, wi, true); }, 1e-3 / kSamples);
        std::vector<double> expected(cells.value.size()), observed(cells.value.size(), 0.0);
        for (size_t i = 0; i < expected.size(); ++i) expected[i] = cells.value[i] * kSamples;
        test::UniformRng rng(0x4a1e + k);
        int inconsistent = 0;
        double rejected = 0.0;
        for (int i = 0; i < kSamples; ++i) {
            const float uLobe = rng.next();
            const auto sample = hair.sample(wo, uLobe, rng.next2D(), true);
            if (!sample) {
                rejected += 1.0;
                continue;
            }
            observed[size_t(binning.cellOf(sample->wi))] += 1.0;
            if (i % 64 == 0) {
                const float pdf = hair.pdf(wo, sample->wi, true);
                const Rgb weight = hair.eval(wo, sample->wi, true) * (std::abs(sample->wi.z) / pdf);
                if (std::abs(sample->pdf - pdf) > 1e-4f * pdf ||
                    std::abs(sample->weight.g - weight.g) > 1e-4f * weight.g ||
                    std::abs(length(sample->wi) - 1.0f) > 1e-5f)
                    ++inconsistent;
            }
        }
        EXPECT_EQ(inconsistent, 0);
        EXPECT_LT(rejected, 1e-4 * kSamples);
        for (size_t i = 0; i < expected.size(); ++i)
            if (expected[i] == 0.0 && observed[i] > 0.0) expected[i] = 1e-3;
        const test::ChiSquareResult result = test::chiSquareTest(observed, expected);
        std::printf("beta_m %.1f, beta_n %.1f: %s\n", s.betaM, s.betaN, result.describe().c_str());
        EXPECT_GT(result.pValue, alpha) << result.describe();
    }
}

}  // namespace
}  // namespace penumbra
