// Measured BRDFs (materials/measured_bsdf.h, materials/measured_bsdf_reader.h). Files of our own
// writing (tests/support/rgl_bsdf_writer.h) tabulate a known BRDF, a rough gold conductor (GGX of
// alpha 0.3, complex Fresnel): read back, they give that BRDF's albedo, follow their own pdf (chi-square),
// agree between RGB, spectral, isotropic, anisotropic and mirrored (reduced) layouts, and every
// malformed file is an InputError that says what is wrong.
//
// Tolerances: the tables interpolate the BRDF bilinearly on grids of 64 x 64 (or 48 x 48) normals and
// 32 x 32 samples, so values differ from the analytic BRDF by the interpolation error, most where the
// NDF is curved most (its peak); integrals of them (the albedo) far less. The tolerance on the albedo,
// 1%, is 2.5 times the largest difference seen over the angles and layouts tested (0.4%); 3% for a
// file of f cos itself (1.3% seen).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "materials/material.h"
#include "materials/measured_bsdf_reader.h"
#include "tests/support/bsdf_test_support.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/rgl_bsdf_writer.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::directionFromAngles;

RoughConductor gold() {
    RoughConductor conductor;
    conductor.eta = {0.143f, 0.374f, 1.442f};
    conductor.k = {3.983f, 2.385f, 1.603f};
    conductor.distribution = MicrofacetDistribution{0.3f, 0.3f, MicrofacetKind::Ggx};
    return conductor;
}

std::string goldFile(const test::TabulationGrid& grid = {}) {
    const RoughConductor conductor = gold();
    return test::tabulateIsotropicGgxBrdf(
        0.3f, [&](Vec3f wo, Vec3f wi) { return conductor.eval(wo, wi, true) * wi.z; }, grid);
}

Material measuredMaterial(const std::string& bytes) {
    return Material(MeasuredBsdf{parseMeasuredBsdf(bytes, "gold.bsdf")});
}

void expectAlbedoOfGold(const Material& measured, const std::string& what, float tolerance = 0.01f) {
    const Material analytic(gold());
    for (const double theta : {0.0, 30.0, 60.0, 80.0})
        for (const double phi : {0.0, 70.0, 200.0}) {
            const Vec3f wo = directionFromAngles(theta, phi);
            const Rgb expected = test::directionalAlbedo(analytic, wo),
                      got = test::directionalAlbedo(measured, wo);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], expected[c], tolerance * expected[c])
                    << what << ": theta " << theta << ", phi " << phi << ", channel " << c;
        }
}

TEST(MeasuredBsdf, TabulatedGoldHasTheAnalyticAlbedo) {
    expectAlbedoOfGold(measuredMaterial(goldFile()), "isotropic RGB file");
}

TEST(MeasuredBsdf, AnisotropicAndReducedLayoutsGiveTheSameBrdf) {
    test::TabulationGrid grid;
    grid.normalGrid = 48;
    grid.phiNodes = 17;
    expectAlbedoOfGold(measuredMaterial(goldFile(grid)), "anisotropic file, all azimuths");
    grid.phiNodes = 9;
    grid.reduction = 2;
    expectAlbedoOfGold(measuredMaterial(goldFile(grid)), "anisotropic file, half the azimuths");
    grid.phiNodes = 5;
    grid.reduction = 4;
    expectAlbedoOfGold(measuredMaterial(goldFile(grid)), "anisotropic file, a quarter of the azimuths");
}

TEST(MeasuredBsdf, FilesWithoutTheJacobianStoreFCos) {
    test::TabulationGrid grid;
    grid.storesJacobian = false;
    // f cos holds the NDF's peak, which bilinear interpolation flattens more than the smooth
    // weight of the other files: up to 1.3% here.
    expectAlbedoOfGold(measuredMaterial(goldFile(grid)), "file with jacobian 0", 0.03f);
}

TEST(MeasuredBsdf, AGreySpectrumIsTheSameGreyInRgb) {
    // A grey BRDF (channel 0 of gold, the same in every channel) as "rgb" and as "spectra" of a flat
    // spectrum: a flat reflectance is exactly grey in RGB (core/colorimetry.h), so the two agree
    // to float rounding.
    const RoughConductor conductor = gold();
    const auto grey = [&](Vec3f wo, Vec3f wi) { return Rgb(conductor.eval(wo, wi, true).r * wi.z); };
    test::TabulationGrid grid;
    grid.thetaNodes = 8;
    const Material rgb = measuredMaterial(test::tabulateIsotropicGgxBrdf(0.3f, grey, grid));
    grid.spectral = true;
    const Material spectral = measuredMaterial(test::tabulateIsotropicGgxBrdf(0.3f, grey, grid));
    test::UniformRng rng(3);
    for (int i = 0; i < 500; ++i) {
        const Vec3f wo = directionFromAngles(80.0 * rng.next(), 360.0 * rng.next());
        const Vec3f wi = directionFromAngles(85.0 * rng.next(), 360.0 * rng.next());
        const Rgb a = rgb.eval(wo, wi, true), b = spectral.eval(wo, wi, true);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], a[0], 1e-5f * a[0] + 1e-7f);
    }
}

TEST(MeasuredBsdf, TwoSidedAndBlackAcrossTheSurface) {
    const Material m = measuredMaterial(goldFile());
    const Vec3f wo = directionFromAngles(40, 10), wi = directionFromAngles(35, 200);
    const Rgb front = m.eval(wo, wi, true), back = m.eval(-wo, -wi, true);
    EXPECT_GT(front.r, 0.0f);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(front[c], back[c]);
    EXPECT_EQ(m.eval(wo, -wi, true).r, 0.0f);
    EXPECT_EQ(m.pdf(wo, -wi, true), 0.0f);
}

// Chi-square of sample() against pdf() over cells around the mirror direction.
TEST(MeasuredBsdf, SamplesFollowThePdf) {
    const Material m = measuredMaterial(goldFile());
    constexpr int kSamples = 200000;
    const std::vector<double> angles{0.0, 35.0, 70.0, 88.0};
    for (const double theta : angles) {
        const Vec3f wo = directionFromAngles(theta, 30.0);
        test::SphereBinning binning;
        binning.frame = Frame::fromNormal(theta == 0.0 ? Vec3f{0, 0, 1} : normalize(reflectAboutZ(wo)));
        binning.gamma = 1.5;
        const test::CellIntegrals integrals = test::integrateOverCells(
            binning, [&](Vec3f wi) { return wi.z > 0.0f ? m.pdf(wo, wi, true) : 0.0f; }, 1e-3 / kSamples, 8,
            2);
        std::vector<double> expected, observed(size_t(binning.cellCount()) + 1, 0.0);
        double mass = 0.0;
        for (double v : integrals.value) {
            mass += v;
            expected.push_back(v * kSamples);
        }
        test::UniformRng rng(0x3ea5u + uint64_t(theta));
        int inconsistent = 0;
        for (int i = 0; i < kSamples; ++i) {
            const auto s = m.sample(wo, rng.next(), rng.next2D(), true);
            if (!s) {
                observed.back() += 1.0;
                continue;
            }
            observed[size_t(binning.cellOf(s->wi))] += 1.0;
            if (i % 16 != 0) continue;
            const float pdf = m.pdf(wo, s->wi, true);
            const Rgb weight = m.eval(wo, s->wi, true) * (s->wi.z / pdf);
            bool ok = std::abs(s->pdf - pdf) <= 1e-3f * pdf;
            for (int c = 0; c < 3; ++c)
                ok = ok && std::abs(s->weight[c] - weight[c]) <= 1e-3f * weight[c] + 1e-6f;
            inconsistent += ok ? 0 : 1;
        }
        EXPECT_EQ(inconsistent, 0) << "theta " << theta;
        expected.push_back(std::max(0.0, 1.0 - mass) * kSamples);
        const test::ChiSquareResult result = test::chiSquareTest(observed, expected);
        EXPECT_GT(result.pValue, test::sidakAlpha(0.01, int(angles.size())))
            << "theta " << theta << ": " << result.describe();
    }
}

// The AOV's albedo is a 32 x 32 grid of sample weights, not an integral: 0.28% from the quadrature
// measured, within the 2% an albedo AOV needs (denoisers use it to separate texture from light).
TEST(MeasuredBsdf, AlbedoForTheAovIsTheNormalIncidenceAlbedo) {
    const Material m = measuredMaterial(goldFile());
    const Rgb expected = test::directionalAlbedo(Material(gold()), {0.0f, 0.0f, 1.0f});
    const Rgb aov = std::get<MeasuredBsdf>(m.model()).reflectanceForAov();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(aov[c], expected[c], 0.02f * expected[c]);
}

// A valid small file, its fields editable.
std::vector<test::TensorFieldToWrite> smallFile() {
    const std::vector<float> ones4(16, 1.0f), ones2(4, 1.0f);
    return {test::byteField("description", "small"),
            test::byteField("jacobian", std::string(1, '\1')),
            test::floatField("theta_i", {2}, {0.0f, 1.0f}),
            test::floatField("phi_i", {1}, {0.0f}),
            test::floatField("ndf", {2, 2}, ones2),
            test::floatField("sigma", {2, 2}, ones2),
            test::floatField("vndf", {1, 2, 2, 2}, std::vector<float>(8, 1.0f)),
            test::floatField("luminance", {1, 2, 2, 2}, std::vector<float>(8, 1.0f)),
            test::floatField("rgb", {1, 2, 3, 2, 2}, std::vector<float>(24, 0.5f))};
}

std::string errorOf(const std::string& bytes) {
    return testing::catchInputError([&] { parseMeasuredBsdf(bytes, "bad.bsdf"); }).what();
}

std::string errorWith(const std::string& name, test::TensorFieldToWrite replacement) {
    std::vector<test::TensorFieldToWrite> fields = smallFile();
    for (test::TensorFieldToWrite& f : fields)
        if (f.name == name) f = std::move(replacement);
    return errorOf(test::writeTensorFile(fields));
}

TEST(MeasuredBsdfReader, ReadsTheSmallFileAndRefusesEveryMalformedOne) {
    ASSERT_NO_THROW(parseMeasuredBsdf(test::writeTensorFile(smallFile()), "small.bsdf"));
    const std::string valid = test::writeTensorFile(smallFile());

    EXPECT_CONTAINS(errorOf("PK\3\4 not a tensor file at all"), "bad.bsdf: not a tensor file");
    EXPECT_CONTAINS(errorOf(valid.substr(0, 40)), "the file is truncated");
    std::string version = valid;
    version[12] = 2;
    EXPECT_CONTAINS(errorOf(version), "tensor file version 2.0");

    std::vector<test::TensorFieldToWrite> fields = smallFile();
    fields.erase(fields.begin() + 5);  // sigma
    EXPECT_CONTAINS(errorOf(test::writeTensorFile(fields)), "the field \"sigma\" is missing");
    fields = smallFile();
    fields.push_back(test::floatField("ndf", {2, 2}, std::vector<float>(4, 1.0f)));
    EXPECT_CONTAINS(errorOf(test::writeTensorFile(fields)), "(\"ndf\"): the name is used twice");
    fields = smallFile();
    fields.back().name = "colour";
    EXPECT_CONTAINS(errorOf(test::writeTensorFile(fields)), "neither \"spectra\" nor \"rgb\"");

    EXPECT_CONTAINS(errorWith("theta_i", test::floatField("theta_i", {2}, {1.0f, 0.5f})),
                    "theta_i is not increasing: theta_i[1] = 0.5 follows 1");
    EXPECT_CONTAINS(errorWith("theta_i", test::floatField("theta_i", {2}, {0.0f, 2.0f})), "theta_i[1] is 2");
    EXPECT_CONTAINS(errorWith("ndf", test::floatField("ndf", {2}, {1.0f, 1.0f})),
                    "\"ndf\" has rank 1, expected 2");
    EXPECT_CONTAINS(errorWith("ndf", test::floatField("ndf", {1, 4}, std::vector<float>(4, 1.0f))),
                    "\"ndf\" has 1 nodes along dimension 0: expected 2 to 32768");
    EXPECT_CONTAINS(errorWith("sigma", test::floatField("sigma", {2, 2}, {1.0f, 0.0f, 1.0f, 1.0f})),
                    "\"sigma\" holds 0 at element 1");
    EXPECT_CONTAINS(errorWith("vndf", test::floatField("vndf", {1, 2, 2, 2}, {1, 1, 1, -1, 1, 1, 1, 1})),
                    "\"vndf\" holds -1 at element 3");
    EXPECT_CONTAINS(
        errorWith("luminance", test::floatField("luminance", {1, 2, 2, 2}, {1, 1, 1, 1, 0, 0, 0, 0})),
        "\"luminance\" is zero everywhere in slice 1");
    EXPECT_CONTAINS(
        errorWith("luminance", test::floatField("luminance", {1, 3, 2, 2}, std::vector<float>(12, 1.0f))),
        "\"luminance\" has shape [1, 3, 2, 2], expected [1, 2, 2, 2]");
    std::vector<float> rgb(24, 0.5f);
    rgb[7] = NAN;
    EXPECT_CONTAINS(errorWith("rgb", test::floatField("rgb", {1, 2, 3, 2, 2}, rgb)),
                    "\"rgb\" holds nan at element 7");
    EXPECT_CONTAINS(errorWith("rgb", test::floatField("rgb", {1, 2, 4, 2, 2}, std::vector<float>(32, 0.5f))),
                    "\"rgb\" has shape [1, 2, 4, 2, 2], expected [1, 2, 3, 2, 2]");
    EXPECT_CONTAINS(errorWith("jacobian", test::floatField("jacobian", {1}, {1.0f})),
                    "\"jacobian\" holds float32 values, expected uint8");
    // Three azimuths spanning 2 pi / 3: a reduction no file uses.
    fields = smallFile();
    fields[3] = test::floatField("phi_i", {3}, {-3.14159f, -2.5f, -1.0472f});
    fields[6] = test::floatField("vndf", {3, 2, 2, 2}, std::vector<float>(24, 1.0f));
    fields[7] = test::floatField("luminance", {3, 2, 2, 2}, std::vector<float>(24, 1.0f));
    fields[8] = test::floatField("rgb", {3, 2, 3, 2, 2}, std::vector<float>(72, 0.5f));
    EXPECT_CONTAINS(errorOf(test::writeTensorFile(fields)), "reduction 1, 2 or 4");
}

TEST(MeasuredBsdfReader, FieldsOutsideTheFileAreRefusedBeforeAnythingIsRead) {
    const std::string valid = test::writeTensorFile(smallFile());
    // The first field's offset (after magic, version, count, name length 2 + "description", rank 2,
    // type 1) pointed past the end; then its extent made enormous (an overflow of extent x size).
    const size_t offsetAt = 12 + 2 + 4 + 2 + 11 + 2 + 1;
    std::string far = valid;
    const uint64_t beyond = uint64_t(1) << 40;
    std::memcpy(far.data() + offsetAt, &beyond, 8);
    EXPECT_CONTAINS(errorOf(far), "field 0 (\"description\") lies outside the file");
    std::string huge = valid;
    const uint64_t extent = uint64_t(1) << 62;
    std::memcpy(huge.data() + offsetAt + 8, &extent, 8);
    EXPECT_CONTAINS(errorOf(huge), "field 0 (\"description\") holds more data than the file");
    std::string rank = valid;
    const uint16_t bigRank = 300;
    std::memcpy(rank.data() + offsetAt - 3, &bigRank, 2);
    EXPECT_CONTAINS(errorOf(rank), "has rank 300: at most 16 is read");
    std::string type = valid;
    type[offsetAt - 1] = 12;
    EXPECT_CONTAINS(errorOf(type), "has element type 12: expected 1 to 11");
}

TEST(MeasuredBsdfReader, FileErrorsNameTheFile) {
    const std::string message =
        testing::catchInputError([] { readMeasuredBsdf("/nonexistent/folder/missing.bsdf"); }).what();
    EXPECT_CONTAINS(message, "missing.bsdf");
}

}  // namespace
}  // namespace penumbra
