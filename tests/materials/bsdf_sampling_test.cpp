// The materials' sampling routines against their densities and values, in the local frame.
//
// Chi-square goodness of fit (pbrt-v4's bsdfs_test, Mitsuba 3's chi2.py): 10^6 directions drawn
// by Material::sample with a fixed seed are counted in the cells of a partition of the sphere
// (20 x 40 cells in (cos theta, phi), see SphereBinning), and the counts are compared with the
// expected counts N * integral of Material::pdf over each cell (adaptive cubature). Samples that
// the routine rejects (a Phong specular direction below the horizon), or draws from a delta lobe
// beside the continuous ones (a subsurface exit's internal reflection), form one more cell, expected
// to hold N * (1 - integral of the pdf over the sphere). Cells expected to hold fewer than 5 are
// pooled (test_statistics.h). The polar axis of the cells is the lobe's axis: +z for diffuse
// lobes, the mirror direction of wo for Phong, with rings made finer near the axis for narrow
// lobes (gamma grows with the exponent), so that a lobe of exponent 1000 (half width 2 degrees)
// still spreads over about a hundred cells.
//
// Significance: each test rejects a correct sampler with probability alpha = 0.01 Sidak-corrected
// for the number of chi-square tests in this file, so that the chance of any false failure is
// 1%; the seed is fixed, so the outcome is reproducible. Errors of the cubature are kept far below
// the counts' noise: each cell's integral is refined until the coarse and fine rules agree within
// a thousandth of a sample or 1e-4 relative, and the bias their remaining errors could add to the
// statistic, sum(error^2 / expected), is checked to stay below 1 (the statistic's own standard
// deviation is about 40).
//
// Discrete (delta) lobes, whose directions are exact, are tested by the frequency of each lobe
// against its Fresnel probability (a two-cell chi-square) and by the exact geometry of each
// direction.
//
// Further checks per case: the sampled pdf and weight equal Material::pdf and
// Material::eval * |cos| / pdf; the mean weight (the albedo) equals an independent 1D integral;
// the density integrates to 1 (to the lobe's share above the horizon for Phong); reciprocity.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "materials/material.h"
#include "tests/support/bsdf_test_support.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::directionFromAngles;
using test::kPiD;

constexpr int kSamples = 1000000;

struct ContinuousCase {
    std::string name;
    Material material;
    double thetaO;  // degrees; > 90 puts wo below the surface (two-sided evaluation)
    double phiO;
};

// The albedo and the sampled density's mass, computed independently of the material code.
struct Reference {
    Rgb albedo;
    double mass;  // integral of the pdf over the sphere = probability that sample() returns a direction
    // The share of the albedo that is energy: 1 but for a subsurface exit, whose diffuse exit's
    // eta^2 restores the radiance that refraction in divided by it.
    double energy = -1.0;  // < 0: the albedo's
};

// A subsurface boundary seen from inside at thetaUp: it reflects F back in (a delta lobe) and lets
// 1 - F out diffusely, times eta^2 (radiance); F the Fresnel reflectance from inside (Hecht).
template <class Surface>
Reference subsurfaceExitReference(const SubsurfaceBoundary<Surface>& b, double thetaUp) {
    const double eta = b.surface.eta, f = test::fresnelHecht(std::cos(thetaUp), 1.0 / eta);
    return {Rgb(float(f + (1.0 - f) * eta * eta)), 1.0 - f, 1.0};
}

Reference referenceOf(const ContinuousCase& c) {
    const double thetaUp = test::radians(c.thetaO > 90.0 ? 180.0 - c.thetaO : c.thetaO);
    if (const Lambert* lambert = std::get_if<Lambert>(&c.material.model())) return {lambert->albedo, 1.0};
    // Reflection and transmission, each R or T over pi on its hemisphere: albedo R + T.
    if (const auto* d = std::get_if<DiffuseTransmission>(&c.material.model()))
        return {d->reflectance + d->transmittance, 1.0};
    if (const auto* b = std::get_if<SubsurfaceBoundary<Dielectric>>(&c.material.model()))
        return subsurfaceExitReference(*b, thetaUp);
    if (const auto* b = std::get_if<SubsurfaceBoundary<RoughDielectric>>(&c.material.model()))
        return subsurfaceExitReference(*b, thetaUp);
    const Phong& p = std::get<Phong>(c.material.model());
    const double share = test::phongLobeShareAbove(p.exponent, thetaUp);
    const double specularAlbedo = test::phongSpecularAlbedo(p.exponent, thetaUp);
    const double pSpecular = p.ks.luminance() / (p.kd.luminance() + p.ks.luminance());
    return {p.kd + p.ks * float(specularAlbedo), (1.0 - pSpecular) + pSpecular * share};
}

std::vector<ContinuousCase> continuousCases() {
    std::vector<ContinuousCase> cases;
    for (double theta : {0.0, 45.0, 80.0, 130.0})
        cases.push_back({"Lambert_theta" + std::to_string(int(theta)),
                         test::makeLambertMaterial({0.9f, 0.5f, 0.1f}), theta, 30.0});
    struct Mix {
        const char* name;
        Rgb kd, ks;
    };
    const Mix mixes[] = {{"Specular", Rgb(0.0f), Rgb(1.0f)},
                         {"Even", Rgb(0.5f), Rgb(0.5f)},
                         {"Coloured", {0.7f, 0.2f, 0.1f}, {0.2f, 0.3f, 0.9f}}};
    for (float n : {1.0f, 10.0f, 100.0f, 1000.0f})
        for (const Mix& mix : mixes)
            for (double theta : {0.0, 50.0, 80.0}) {
                // The mixed lobes at normal incidence add little beyond the pure lobe there.
                if (theta == 0.0 && mix.name != std::string("Specular")) continue;
                cases.push_back({"Phong_n" + std::to_string(int(n)) + "_" + mix.name + "_theta" +
                                     std::to_string(int(theta)),
                                 test::makePhongMaterial(mix.kd, mix.ks, n), theta, 200.0});
            }
    struct Transmitter {
        const char* name;
        Rgb r, t;
    };
    const Transmitter transmitters[] = {{"Coloured", {0.6f, 0.3f, 0.1f}, {0.2f, 0.5f, 0.3f}},
                                        {"TransmitOnly", Rgb(0.0f), {0.9f, 0.6f, 0.3f}},
                                        {"ReflectOnly", {0.3f, 0.6f, 0.9f}, Rgb(0.0f)}};
    for (const Transmitter& d : transmitters)
        for (double theta : {0.0, 45.0, 80.0, 130.0})
            cases.push_back(
                {std::string("DiffuseTransmission_") + d.name + "_theta" + std::to_string(int(theta)),
                 Material(DiffuseTransmission{d.r, d.t}), theta, 60.0});
    // The exit of a subsurface walk (wo inside, below the outward normal), smooth and rough.
    // (Inside at 40 and 10 degrees from the normal, within the critical angle of 48.8 degrees.)
    for (double theta : {140.0, 170.0})
        cases.push_back({"SubsurfaceExit_theta" + std::to_string(int(theta)),
                         Material(SubsurfaceBoundary<Dielectric>{Dielectric{1.33f}}), theta, 20.0});
    RoughDielectric rough;
    rough.eta = 1.5f;
    rough.distribution.alphaX = rough.distribution.alphaY = 0.3f;
    cases.push_back(
        {"SubsurfaceExitRough_theta145", Material(SubsurfaceBoundary<RoughDielectric>{rough}), 145.0, 20.0});
    // wo below the surface: the two-sided model mirrors itself.
    cases.push_back(
        {"Phong_n10_Even_theta120", test::makePhongMaterial(Rgb(0.5f), Rgb(0.5f), 10.0f), 120.0, 75.0});
    cases.push_back({"Phong_n1000_Specular_theta150", test::makePhongMaterial(Rgb(0.0f), Rgb(1.0f), 1000.0f),
                     150.0, 310.0});
    return cases;
}

// ---- Delta lobes ----

struct DeltaCase {
    std::string name;
    Material material;
    double thetaO;       // degrees, wo.z = cos(thetaO)
    bool front;          // wo on the geometric front (outside of a dielectric)
    double reflectance;  // expected probability of reflection, computed independently
};

double hechtThin(double cosTheta, double eta) {
    const double r = test::fresnelHecht(cosTheta, eta), t = 1.0 - r;
    return r < 1.0 ? r + t * t * r / (1.0 - r * r) : 1.0;
}
double schlick(double cosTheta, double eta) {  // eta = eta_t / eta_i
    const double r0 = (eta - 1.0) * (eta - 1.0) / ((eta + 1.0) * (eta + 1.0));
    double c = cosTheta;
    if (eta < 1.0) {
        const double sin2T = (1.0 - c * c) / (eta * eta);
        if (sin2T >= 1.0) return 1.0;
        c = std::sqrt(1.0 - sin2T);
    }
    return r0 + (1.0 - r0) * std::pow(1.0 - c, 5.0);
}

std::vector<DeltaCase> deltaCases() {
    std::vector<DeltaCase> cases;
    const double eta = 1.5;
    auto cosd = [](double degrees) { return std::cos(test::radians(degrees)); };
    // Entering from outside (wo above, front), the far side has index 1.5.
    for (double theta : {0.0, 45.0, 80.0})
        cases.push_back({"GlassEnter_theta" + std::to_string(int(theta)), test::makeDielectricMaterial(1.5f),
                         theta, true, test::fresnelHecht(cosd(theta), eta)});
    // Leaving (wo inside, below the outward shading normal): critical angle asin(1 / 1.5) = 41.81 deg.
    for (double theta : {30.0, 41.0, 41.9, 60.0})
        cases.push_back({"GlassLeave_theta" + std::to_string(int(theta * 10)),
                         test::makeDielectricMaterial(1.5f), 180.0 - theta, false,
                         test::fresnelHecht(cosd(theta), 1.0 / eta)});
    cases.push_back({"WaterEnter_theta30", test::makeDielectricMaterial(1.33f), 30.0, true,
                     test::fresnelHecht(cosd(30.0), 1.33)});
    cases.push_back({"GlassSchlickEnter_theta60", test::makeDielectricMaterial(1.5f, FresnelModel::Schlick),
                     60.0, true, schlick(cosd(60.0), eta)});
    cases.push_back({"GlassSchlickLeave_theta35", test::makeDielectricMaterial(1.5f, FresnelModel::Schlick),
                     145.0, false, schlick(cosd(35.0), 1.0 / eta)});
    cases.push_back({"GlassSchlickLeave_theta50", test::makeDielectricMaterial(1.5f, FresnelModel::Schlick),
                     130.0, false, 1.0});
    for (double theta : {0.0, 70.0})
        cases.push_back({"ThinGlass_theta" + std::to_string(int(theta)),
                         test::makeThinDielectricMaterial(1.5f), theta, true, hechtThin(cosd(theta), eta)});
    cases.push_back({"ThinGlassBack_theta110", test::makeThinDielectricMaterial(1.5f), 110.0, false,
                     hechtThin(cosd(70.0), eta)});
    return cases;
}

// All chi-square tests of this file share the 1% family-wise significance.
void PrintTo(const ContinuousCase& c, std::ostream* out) { *out << c.name; }
void PrintTo(const DeltaCase& c, std::ostream* out) { *out << c.name; }

double perTestAlpha() { return test::sidakAlpha(0.01, int(continuousCases().size() + deltaCases().size())); }

// ---- Continuous lobes ----

class ContinuousLobe : public ::testing::TestWithParam<ContinuousCase> {};

TEST_P(ContinuousLobe, SamplesFollowThePdf) {
    const ContinuousCase& c = GetParam();
    const Material& material = c.material;
    const bool front = c.thetaO <= 90.0;  // two-sided models: the side does not matter
    const Vec3f wo = directionFromAngles(c.thetaO, c.phiO);

    test::SphereBinning binning;
    if (const Phong* phong = test::phongOf(material)) {
        binning.frame = Frame::fromNormal(normalize(reflectAboutZ(wo)));
        binning.gamma = 1.0 + std::log10(std::max(1.0f, phong->exponent)) * 2.0 / 3.0;
    }

    // Expected counts, to 1e-3 samples per cell (absolute) or 1e-4 relative.
    const test::CellIntegrals cells = test::integrateOverCells(
        binning, [&](Vec3f wi) { return material.pdf(wo, wi, front); }, 1e-3 / kSamples);
    std::vector<double> expected(cells.value.size());
    double mass = 0.0, cubatureChiSquare = 0.0;
    for (size_t i = 0; i < expected.size(); ++i) {
        mass += cells.value[i];
        expected[i] = cells.value[i] * kSamples;
        const double error = cells.error[i] * kSamples;
        cubatureChiSquare += error * error / std::max(expected[i], 5.0);
    }
    // The cubature's errors could bias the statistic by at most about sum(error^2 / expected):
    // keep that below 1, against the statistic's standard deviation sqrt(2 dof) of about 40.
    EXPECT_LT(cubatureChiSquare, 1.0);

    // The density integrates to 1, or to the share of the lobe above the horizon. Float unit
    // vectors are unit to about 1e-7, and the lobe raises cos(alpha) to the power n, so the float
    // pdf's integral is exact only to about n * 1e-7; a lost normalization factor (n + 2 instead of
    // n + 1, a missing lobe probability) shows as an error of 1e-3 or more.
    const Reference reference = referenceOf(c);
    const double exponent = test::phongOf(material) ? test::phongOf(material)->exponent : 0.0;
    EXPECT_NEAR(mass, reference.mass, 1e-5 + 1e-7 * exponent);
    if (c.thetaO == 0.0) {
        EXPECT_NEAR(mass, 1.0, 1e-5 + 1e-7 * exponent);
    }

    // Observed counts, with the samples' own pdf and weight checked against pdf() and eval().
    std::vector<double> observed(expected.size(), 0.0);
    double rejected = 0.0;
    double weightSum[3] = {0, 0, 0}, weightSquares[3] = {0, 0, 0};
    int inconsistent = 0;
    std::string firstInconsistency;
    test::UniformRng rng(0x5eed0000u + uint64_t(c.thetaO * 7 + c.phiO));
    for (int i = 0; i < kSamples; ++i) {
        const float uLobe = rng.next();
        const Vec2f u = rng.next2D();
        const auto s = material.sample(wo, uLobe, u, front);
        if (!s || s->isSpecular()) {
            // A delta lobe beside the continuous ones (a subsurface exit's internal reflection):
            // counted with the rejections, outside the density; its weight in the albedo.
            rejected += 1.0;
            if (s) {
                for (int ch = 0; ch < 3; ++ch) {
                    weightSum[ch] += s->weight[ch];
                    weightSquares[ch] += double(s->weight[ch]) * s->weight[ch];
                }
                if (s->wi != reflectAboutZ(wo) || s->weight != Rgb(1.0f)) ++inconsistent;
            }
            continue;
        }
        observed[size_t(binning.cellOf(s->wi))] += 1.0;
        if (!(s->pdf > 0.0f) || !s->weight.isFinite()) ++inconsistent;  // never where the density is 0
        for (int ch = 0; ch < 3; ++ch) {
            weightSum[ch] += s->weight[ch];
            weightSquares[ch] += double(s->weight[ch]) * s->weight[ch];
        }
        if (i % 8 == 0) {
            // pdf and weight: float arithmetic of the same quantities, so agreement to 1e-5 relative.
            const float pdf = material.pdf(wo, s->wi, front);
            const Rgb expectedWeight = material.eval(wo, s->wi, front) * (std::abs(s->wi.z) / pdf);
            const bool transmits = any(material.flags() & BsdfFlags::Transmission);
            bool ok = !s->isSpecular() && (transmits || !s->isTransmission()) &&
                      s->isTransmission() == (s->wi.z * wo.z < 0.0f) &&
                      std::abs(s->pdf - pdf) <= 1e-5f * pdf && std::abs(length(s->wi) - 1.0f) < 1e-5f;
            for (int ch = 0; ch < 3; ++ch)
                ok = ok && std::abs(s->weight[ch] - expectedWeight[ch]) <= 1e-5f * expectedWeight[ch] + 1e-7f;
            if (!ok && inconsistent++ == 0)
                firstInconsistency = "wi (" + std::to_string(s->wi.x) + ", " + std::to_string(s->wi.y) +
                                     ", " + std::to_string(s->wi.z) + "): pdf " + std::to_string(s->pdf) +
                                     " vs " + std::to_string(pdf) + ", weight.r " +
                                     std::to_string(s->weight.r) + " vs " + std::to_string(expectedWeight.r);
        }
    }
    EXPECT_EQ(inconsistent, 0) << firstInconsistency;

    observed.push_back(rejected);
    expected.push_back(std::max(0.0, (1.0 - mass) * kSamples));
    // A cell that the horizon cuts into a thin sliver can receive a few samples although every
    // cubature point fell on the zero side (its mass is ~1e-6). Such cells get a token expected
    // count, so that they are pooled with the other small cells instead of failing the test
    // outright; samples where the density really is 0 are caught above (pdf > 0 for every sample).
    for (size_t i = 0; i + 1 < expected.size(); ++i)
        if (expected[i] == 0.0 && observed[i] > 0.0) expected[i] = 1e-3;
    const test::ChiSquareResult result = test::chiSquareTest(observed, expected);
    EXPECT_GT(result.pValue, perTestAlpha()) << result.describe() << "; " << rejected << " rejected";

    // Albedo: the mean weight (rejections count 0) estimates the integral of f cos over the
    // hemisphere, which the reference computes by 1D quadrature. 5 standard errors of the mean,
    // from the sample variance (a false failure has probability below 1e-6 per channel).
    for (int ch = 0; ch < 3; ++ch) {
        const double mean = weightSum[ch] / kSamples;
        const double variance = std::max(0.0, weightSquares[ch] / kSamples - mean * mean);
        EXPECT_TRUE(test::withinSigmas(mean, reference.albedo[ch], std::sqrt(variance / kSamples) + 1e-7))
            << "channel " << ch;
        const double energy = reference.energy < 0.0 ? reference.albedo[ch] : reference.energy;
        EXPECT_LE(energy, 1.0 + 1e-6);  // energy conservation of the model itself
    }
}

INSTANTIATE_TEST_SUITE_P(Materials, ContinuousLobe, ::testing::ValuesIn(continuousCases()),
                         [](const ::testing::TestParamInfo<ContinuousCase>& info) {
                             return info.param.name;
                         });

// ---- Delta lobes ----

class DeltaLobe : public ::testing::TestWithParam<DeltaCase> {};

TEST_P(DeltaLobe, LobeFrequenciesFollowFresnelAndDirectionsAreExact) {
    const DeltaCase& c = GetParam();
    const Vec3f wo = directionFromAngles(c.thetaO, 35.0);
    const Dielectric* dielectric = std::get_if<Dielectric>(&c.material.model());
    // Relative index eta(wi side) / eta(wo side) of a refraction (1 through a thin pane).
    const float eta = !dielectric ? 1.0f : (c.front ? dielectric->eta : 1.0f / dielectric->eta);

    EXPECT_TRUE(c.material.isPurelySpecular());
    EXPECT_EQ(c.material.pdf(wo, reflectAboutZ(wo), c.front), 0.0f);
    EXPECT_TRUE(c.material.eval(wo, reflectAboutZ(wo), c.front).isBlack());

    double reflected = 0, transmitted = 0;
    int bad = 0;
    std::string firstBad;
    test::UniformRng rng(0xde17a000u + uint64_t(c.thetaO * 10));
    for (int i = 0; i < kSamples; ++i) {
        const float uLobe = rng.next();
        const auto s = c.material.sample(wo, uLobe, rng.next2D(), c.front);
        if (!s) {
            ++bad;
            continue;
        }
        bool ok = s->isSpecular();
        if (!s->isTransmission()) {
            reflected += 1;
            // Mirror direction exactly, weight 1, pdf = probability of reflecting.
            ok = ok && s->wi == reflectAboutZ(wo) && s->weight == Rgb(1.0f) && s->eta == 1.0f &&
                 std::abs(s->pdf - c.reflectance) < 2e-5;
        } else {
            transmitted += 1;
            // Snell: sin(theta_t) = sin(theta_i) / eta; the other side; the azimuth turned by 180
            // degrees (wi's tangential part points opposite to wo's). Float accuracy: 1e-5.
            const double sinI = std::hypot(double(wo.x), double(wo.y));
            const double sinT = std::hypot(double(s->wi.x), double(s->wi.y));
            const double tangentialDot = double(wo.x) * s->wi.x + double(wo.y) * s->wi.y;
            ok = ok && wo.z * s->wi.z < 0.0f && std::abs(sinT * eta - sinI) < 1e-5 && tangentialDot <= 1e-7 &&
                 std::abs(double(length(s->wi)) - 1.0) < 1e-5 && std::abs(double(s->eta) - eta) < 1e-6 &&
                 std::abs(double(s->weight.g) - 1.0 / (double(eta) * eta)) < 1e-6 &&
                 std::abs(s->pdf - (1.0 - c.reflectance)) < 2e-5;
            if (!dielectric) ok = ok && s->wi == -wo;  // a thin pane does not bend light
        }
        if (!ok && bad++ == 0)
            firstBad = "wi (" + std::to_string(s->wi.x) + ", " + std::to_string(s->wi.y) + ", " +
                       std::to_string(s->wi.z) + ") transmission " + std::to_string(s->isTransmission()) +
                       " pdf " + std::to_string(s->pdf) + " weight " + std::to_string(s->weight.g);
    }
    EXPECT_EQ(bad, 0) << firstBad;
    const test::ChiSquareResult result = test::chiSquareTest(
        {reflected, transmitted}, {kSamples * c.reflectance, kSamples * (1.0 - c.reflectance)});
    EXPECT_GT(result.pValue, perTestAlpha()) << result.describe() << "; expected reflectance "
                                             << c.reflectance << ", observed " << reflected / kSamples;
}

INSTANTIATE_TEST_SUITE_P(Materials, DeltaLobe, ::testing::ValuesIn(deltaCases()),
                         [](const ::testing::TestParamInfo<DeltaCase>& info) { return info.param.name; });

// The chi-square test must be able to fail: a Phong sampler whose lobe is drawn with a slightly
// wrong exponent (n + 1 = 11 sampled as 12), or whose lobe choice ignores the luminance weights, is
// rejected by the same machinery.
TEST(ChiSquarePower, RejectsWrongExponentAndWrongLobeChoice) {
    const Vec3f wo = directionFromAngles(50.0, 200.0);
    const Material right = test::makePhongMaterial(Rgb(0.0f), Rgb(1.0f), 10.0f);
    const Material wrongExponent = test::makePhongMaterial(Rgb(0.0f), Rgb(1.0f), 11.0f);
    const Material rightMix = test::makePhongMaterial(Rgb(0.5f), Rgb(0.5f), 10.0f);
    const Material wrongMix =
        test::makePhongMaterial(Rgb(0.6f), Rgb(0.4f), 10.0f);  // a 60:40 choice instead of 50:50
    for (auto [sampler, reference] : {std::pair{&wrongExponent, &right}, std::pair{&wrongMix, &rightMix}}) {
        test::SphereBinning binning;
        binning.frame = Frame::fromNormal(reflectAboutZ(wo));
        std::vector<double> expected =
            test::integrateOverCells(
                binning, [&](Vec3f wi) { return reference->pdf(wo, wi, true); }, 1e-3 / kSamples)
                .value;
        double mass = 0;
        for (double& e : expected) mass += e, e *= kSamples;
        std::vector<double> observed(expected.size(), 0.0);
        double rejected = 0;
        test::UniformRng rng(99);
        for (int i = 0; i < kSamples; ++i) {
            const float uLobe = rng.next();
            const auto s = sampler->sample(wo, uLobe, rng.next2D(), true);
            if (s)
                observed[size_t(binning.cellOf(s->wi))] += 1;
            else
                rejected += 1;
        }
        observed.push_back(rejected);
        expected.push_back(std::max(0.0, 1.0 - mass) * kSamples);
        EXPECT_LT(test::chiSquareTest(observed, expected).pValue, perTestAlpha());
    }
}

// f(wo, wi) = f(wi, wo) for the non-delta lobes, over random pairs on one side (both sides of
// the two-sided models). Float tolerance: cos(alpha) carries a few 1e-7 of rounding, which
// cos^n(alpha) turns into a relative error of about n * 3e-7 / cos(alpha).
TEST(Reciprocity, LambertAndPhong) {
    const Material materials[] = {test::makeLambertMaterial({0.2f, 0.5f, 0.8f}),
                                  test::makePhongMaterial({0.3f, 0.2f, 0.1f}, {0.6f, 0.7f, 0.8f}, 1.0f),
                                  test::makePhongMaterial(Rgb(0.5f), Rgb(0.5f), 30.0f),
                                  test::makePhongMaterial(Rgb(0.1f), Rgb(0.9f), 1000.0f)};
    test::UniformRng rng(4);
    for (const Material& m : materials) {
        const double n = test::phongOf(m) ? test::phongOf(m)->exponent : 0.0;
        int checked = 0;
        for (int i = 0; i < 20000; ++i) {
            Vec3f a = sampleUniformSphere(rng.next2D()), b = sampleUniformSphere(rng.next2D());
            if (test::phongOf(m) && i % 2 == 0) {
                // Half the pairs near the lobe's peak, where cos^n is not negligible.
                b = normalize(reflectAboutZ(a) + sampleUniformSphere(rng.next2D()) * float(3.0 / (n + 3.0)));
            }
            if (a.z * b.z <= 0.0f) {
                EXPECT_TRUE(m.eval(a, b, true).isBlack());  // reflectors only: no transmission
                continue;
            }
            const Rgb fab = m.eval(a, b, true), fba = m.eval(b, a, true);
            const double cosAlpha = std::max(1e-3, double(dot(reflectAboutZ(a), b)));
            const double tolerance = 1e-6 + 3e-7 * (n + 1.0) / cosAlpha;
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(fab[ch], fba[ch], tolerance * std::max(fab[ch], fba[ch]))
                    << "a (" << a.x << ", " << a.y << ", " << a.z << ") b (" << b.x << ", " << b.y << ", "
                    << b.z << ")";
            ++checked;
        }
        EXPECT_GT(checked, 5000);
    }
}

// One-sided reflectors are black from the back: no value, no density, no sample.
TEST(Sides, OneSidedIsBlackFromTheBack) {
    for (const Material& twoSided :
         {test::makeLambertMaterial(Rgb(0.8f)), test::makePhongMaterial(Rgb(0.4f), Rgb(0.5f), 20.0f)}) {
        const Vec3f wo = directionFromAngles(140.0, 10.0), wi = directionFromAngles(120.0, 200.0);
        Material m = twoSided;
        EXPECT_FALSE(m.eval(wo, wi, false).isBlack());
        EXPECT_GT(m.pdf(wo, wi, false), 0.0f);
        EXPECT_TRUE(m.sample(wo, 0.3f, {0.4f, 0.6f}, false).has_value());
        m = Material(twoSided.model(), false);
        EXPECT_TRUE(m.eval(wo, wi, false).isBlack());
        EXPECT_EQ(m.pdf(wo, wi, false), 0.0f);
        EXPECT_FALSE(m.sample(wo, 0.3f, {0.4f, 0.6f}, false).has_value());
        // The front still reflects.
        EXPECT_FALSE(m.eval(-wo, -wi, true).isBlack());
    }
}

// The documented highlight widths: cos^n(alpha_half) = 1/2.
TEST(PhongExponent, HalfWidthOfTheLobe) {
    const std::pair<float, double> widths[] = {
        {1.0f, 60.0}, {10.0f, 21.1}, {100.0f, 6.7}, {1000.0f, 2.1}, {10000.0f, 0.67}};
    for (auto [n, degrees] : widths) {
        const double half = std::acos(std::pow(0.5, 1.0 / n)) * 180.0 / kPiD;
        EXPECT_NEAR(half, degrees, 0.02 * degrees) << "n = " << n;  // the table rounds to 2 digits
        // And the model's own lobe falls to half there.
        const Material m = test::makePhongMaterial(Rgb(0.0f), Rgb(1.0f), n);
        const Vec3f wo{0.0f, 0.0f, 1.0f};
        const Rgb peak = m.eval(wo, wo, true);
        const Rgb atHalf = m.eval(wo, directionFromAngles(half, 0.0), true);
        EXPECT_NEAR(atHalf.g / peak.g, 0.5, 2e-3) << "n = " << n;
    }
}

// A subsurface boundary seen from outside is its interface: the same samples, values and
// densities as the dielectric alone (whose tests are above and in microfacet_test.cpp).
TEST(SubsurfaceBoundary, FromOutsideItIsItsInterface) {
    RoughDielectric rough;
    rough.eta = 1.4f;
    rough.distribution.alphaX = rough.distribution.alphaY = 0.2f;
    const Material boundary(SubsurfaceBoundary<RoughDielectric>{rough}), interface(rough);
    const Material smoothBoundary(SubsurfaceBoundary<Dielectric>{Dielectric{1.4f}}), smooth(Dielectric{1.4f});
    EXPECT_FALSE(smoothBoundary.isPurelySpecular());  // light is sampled where a walk leaves
    test::UniformRng rng(0x5b5b);
    for (int i = 0; i < 1000; ++i) {
        const Vec3f wo = directionFromAngles(80.0 * rng.next(), 360.0 * rng.next());
        const float uLobe = rng.next();
        const Vec2f u = rng.next2D();
        const auto a = boundary.sample(wo, uLobe, u, true), b = interface.sample(wo, uLobe, u, true);
        ASSERT_EQ(a.has_value(), b.has_value());
        if (a) {
            EXPECT_EQ(a->wi, b->wi);
            EXPECT_EQ(a->weight, b->weight);
            EXPECT_EQ(a->pdf, b->pdf);
            EXPECT_EQ(boundary.eval(wo, a->wi, true), interface.eval(wo, a->wi, true));
        }
        const auto c = smoothBoundary.sample(wo, uLobe, u, true), d = smooth.sample(wo, uLobe, u, true);
        ASSERT_TRUE(c && d);
        EXPECT_EQ(c->wi, d->wi);
        EXPECT_EQ(c->weight, d->weight);
        EXPECT_EQ(c->eta, d->eta);
    }
}

}  // namespace
}  // namespace penumbra
