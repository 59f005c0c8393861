// The layered BSDF (materials/layered_bsdf.h), pbrt-v4's coated materials, against closed forms
// and against itself: its three estimators (eval, sample and the pdf estimate) are stochastic, so
// every check here is a mean over many independent walks with a tolerance of 5 standard errors
// of that mean (the errors measured from the samples' own spread; fixed seeds).
//   - A smooth coat over a Lambertian base with a clear, thin slab has the closed form of
//     Weidlich and Wilkie's coated diffuse: albedo F + (1 - F) rho (1 - F_int) / (1 - rho F_int),
//     f = rho (1 - F(wo)) (1 - F(wi)) / (pi eta^2 (1 - rho F_int)); 1 for rho = 1 (white furnace).
//   - A smooth coat over a smooth conductor is a geometric series of specular paths:
//     R = F + (1 - F)^2 Rc T^2 / (1 - F Rc T^2), Rc the conductor's Fresnel relative to the coat at
//     the refracted angle and T the slab's transmittance along it.
//   - A scattering, non-absorbing slab over a white base conserves energy.
//   - Rough coats: the mean sample weight equals the integral of eval cos (two independent
//     estimators of the albedo), and eval is reciprocal in expectation.
#include "materials/layered_bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "materials/fresnel.h"
#include "tests/support/bsdf_test_support.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::kPiD;

constexpr float kThin = std::numeric_limits<float>::min();

// A mean with its standard error measured from the samples' spread.
struct Estimate {
    double sum = 0, sumSquares = 0;
    int n = 0;
    void add(double v) { sum += v, sumSquares += v * v, ++n; }
    double mean() const { return sum / n; }
    double standardError() const {
        const double m = mean();
        // At least the float rounding of a weight near 1, for estimators of (almost) no variance.
        return std::max(std::sqrt(std::max(sumSquares / n - m * m, 0.0) / (n - 1)), 1e-6);
    }
};

bool isSmoothCoat(const LayeredBsdf& b) {
    return std::max(b.coatDistribution.alphaX, b.coatDistribution.alphaY) < kSmoothAlpha;
}

Vec3f direction(float thetaDegrees, float phiDegrees = 0.0f) {
    const float t = thetaDegrees * kPi / 180.0f, p = phiDegrees * kPi / 180.0f;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// The mean weight of sample() from wo, channel c: the directional albedo.
Estimate sampledAlbedo(const LayeredBsdf& bsdf, Vec3f wo, int c, int n, uint64_t seed) {
    test::UniformRng rng(seed);
    Estimate e;
    for (int i = 0; i < n; ++i) {
        const float uLobe = rng.next();
        const std::optional<BsdfSample> s = bsdf.sample(wo, uLobe, rng.next2D(), true);
        e.add(s ? double(s->weight[c]) : 0.0);
    }
    return e;
}

// The integral of eval cos over the hemisphere, by cosine-weighted directions: mean of pi f.
Estimate evaluatedAlbedo(const LayeredBsdf& bsdf, Vec3f wo, int c, int n, uint64_t seed) {
    test::UniformRng rng(seed);
    Estimate e;
    for (int i = 0; i < n; ++i) {
        const Vec3f wi = sampleCosineHemisphere(rng.next2D());
        e.add(double(bsdf.eval(wo, wi, true)[c]) * kPiD);
    }
    return e;
}

LayeredBsdf coatedDiffuse(float rho, float eta) {
    LayeredBsdf b;
    b.eta = eta;
    b.baseAlbedo = Rgb(rho);
    b.thickness = kThin;
    b.maxDepth = 100;
    return b;
}

TEST(LayeredBsdf, SmoothCoatOverLambertHasTheClosedForm) {
    for (const float eta : {1.5f, 1.33f}) {
        const double fInt = diffuseFresnelReflectance(1.0 / eta);
        for (const float rho : {1.0f, 0.5f}) {
            const LayeredBsdf bsdf = coatedDiffuse(rho, eta);
            for (const float theta : {0.0f, 40.0f, 75.0f}) {
                const Vec3f wo = direction(theta, 30.0f);
                const double F = fresnelDielectric(wo.z, eta);
                const double exact = F + (1.0 - F) * rho * (1.0 - fInt) / (1.0 - rho * fInt);
                const Estimate sampled = sampledAlbedo(bsdf, wo, 0, 200000, 7);
                EXPECT_TRUE(test::withinSigmas(sampled.mean(), exact, sampled.standardError()))
                    << "sample(), eta " << eta << " rho " << rho << " theta " << theta;
                // eval leaves out the coat's mirror reflection (a delta).
                const Estimate evaluated = evaluatedAlbedo(bsdf, wo, 0, 200000, 8);
                EXPECT_TRUE(test::withinSigmas(evaluated.mean(), exact - F, evaluated.standardError()))
                    << "eval(), eta " << eta << " rho " << rho << " theta " << theta;
            }
        }
    }
}

TEST(LayeredBsdf, SmoothCoatOverLambertEvaluatesTheClosedFormPointwise) {
    // eval's walks are seeded by the direction pair: directions a few ulps apart give independent
    // estimates of (almost) the same value.
    const float eta = 1.5f, rho = 0.7f;
    const LayeredBsdf bsdf = coatedDiffuse(rho, eta);
    const double fInt = diffuseFresnelReflectance(1.0 / eta);
    for (const auto& [thetaO, thetaI] : {std::pair{10.0f, 50.0f}, std::pair{60.0f, 20.0f}}) {
        const Vec3f wo = direction(thetaO, 0.0f);
        const Vec3f wi = direction(thetaI, 140.0f);
        const double exact = rho * (1.0 - fresnelDielectric(wo.z, eta)) *
                             (1.0 - fresnelDielectric(wi.z, eta)) / (kPiD * eta * eta * (1.0 - rho * fInt));
        Estimate e;
        for (int i = 0; i < 50000; ++i) {
            const Vec3f jittered{wi.x + float(i) * 1e-9f, wi.y, wi.z};
            e.add(bsdf.eval(wo, jittered, true).g);
        }
        EXPECT_TRUE(test::withinSigmas(e.mean(), exact, e.standardError())) << thetaO << " " << thetaI;
    }
}

TEST(LayeredBsdf, SmoothCoatOverSmoothConductorIsAGeometricSeries) {
    LayeredBsdf bsdf;
    bsdf.eta = 1.5f;
    bsdf.base = LayeredBsdf::Base::Conductor;
    bsdf.conductorEta = {0.2f, 0.9f, 1.1f};  // gold-like, relative to the outside
    bsdf.conductorK = {3.9f, 2.4f, 1.8f};
    bsdf.thickness = 0.3f;
    bsdf.maxDepth = 50;
    for (const float theta : {0.0f, 45.0f, 80.0f}) {
        const Vec3f wo = direction(theta);
        const float F = fresnelDielectric(wo.z, bsdf.eta);
        const float sinT = std::sqrt(1.0f - wo.z * wo.z) / bsdf.eta;
        const float cosT = std::sqrt(1.0f - sinT * sinT);
        const Rgb rc = fresnelComplex(cosT, bsdf.conductorEta / bsdf.eta, bsdf.conductorK / bsdf.eta);
        const double t2 = std::exp(-2.0 * bsdf.thickness / cosT);
        for (int c = 0; c < 3; ++c) {
            const double exact = F + (1.0 - F) * (1.0 - F) * rc[c] * t2 / (1.0 - F * rc[c] * t2);
            const Estimate e = sampledAlbedo(bsdf, wo, c, 200000, 11 + c);
            EXPECT_TRUE(test::withinSigmas(e.mean(), exact, e.standardError())) << theta << " channel " << c;
        }
        // Every path is a delta: nothing to evaluate.
        EXPECT_EQ(bsdf.eval(wo, direction(30.0f, 180.0f), true), Rgb(0.0f));
        EXPECT_EQ(bsdf.pdf(wo, direction(30.0f, 180.0f), true), 0.0f);
    }
}

TEST(LayeredBsdf, ScatteringSlabOverWhiteBaseConservesEnergy) {
    for (const float g : {0.0f, 0.6f, -0.4f}) {
        LayeredBsdf bsdf = coatedDiffuse(1.0f, 1.5f);
        bsdf.thickness = 1.0f;
        bsdf.albedo = Rgb(1.0f);
        bsdf.g = g;
        bsdf.maxDepth = 1000;
        for (const float theta : {20.0f, 70.0f}) {
            const Estimate e = sampledAlbedo(bsdf, direction(theta), 1, 100000, 21);
            EXPECT_TRUE(test::withinSigmas(e.mean(), 1.0, e.standardError()))
                << "g " << g << " theta " << theta;
            const Estimate f = evaluatedAlbedo(bsdf, direction(theta), 1, 100000, 22);
            // eval leaves out the coat's mirror reflection.
            const double F = fresnelDielectric(direction(theta).z, 1.5f);
            EXPECT_TRUE(test::withinSigmas(f.mean(), 1.0 - F, f.standardError()))
                << "g " << g << " theta " << theta;
        }
    }
}

TEST(LayeredBsdf, RoughCoatsSampleWhatTheyEvaluate) {
    LayeredBsdf diffuse = coatedDiffuse(0.6f, 1.5f);
    diffuse.coatDistribution = {0.3f, 0.3f, MicrofacetKind::Ggx};
    diffuse.thickness = 0.05f;
    LayeredBsdf metal;
    metal.base = LayeredBsdf::Base::Conductor;
    metal.conductorEta = {0.2f, 0.9f, 1.1f};
    metal.conductorK = {3.9f, 2.4f, 1.8f};
    metal.conductorDistribution = {0.2f, 0.4f, MicrofacetKind::Ggx};
    metal.coatDistribution = {0.1f, 0.1f, MicrofacetKind::Ggx};
    LayeredBsdf hazy = metal;  // a smooth coat over a rough metal, with a scattering slab
    hazy.coatDistribution = {0.0f, 0.0f, MicrofacetKind::Ggx};
    hazy.albedo = {0.8f, 0.5f, 0.2f};
    hazy.g = 0.3f;
    hazy.thickness = 0.2f;
    for (const LayeredBsdf* bsdf : {&diffuse, &metal, &hazy})
        for (const float theta : {15.0f, 65.0f}) {
            const Vec3f wo = direction(theta, 60.0f);
            const Estimate sampled = sampledAlbedo(*bsdf, wo, 2, 200000, 31);
            // The smooth coat's mirror reflection is sampled, not evaluated.
            const double mirror = isSmoothCoat(*bsdf) ? double(fresnelDielectric(wo.z, bsdf->eta)) : 0.0;
            const Estimate evaluated = evaluatedAlbedo(*bsdf, wo, 2, 200000, 32);
            const double both = std::hypot(sampled.standardError(), evaluated.standardError());
            EXPECT_TRUE(test::withinSigmas(sampled.mean(), evaluated.mean() + mirror, both))
                << (bsdf == &diffuse ? "diffuse"
                    : bsdf == &metal ? "metal"
                                     : "hazy")
                << " theta " << theta;
        }
}

TEST(LayeredBsdf, ReciprocalInExpectationAndTwoSided) {
    LayeredBsdf bsdf = coatedDiffuse(0.6f, 1.5f);
    bsdf.coatDistribution = {0.25f, 0.25f, MicrofacetKind::Ggx};
    bsdf.thickness = 0.1f;
    const Vec3f a = direction(20.0f, 10.0f), b = direction(55.0f, 200.0f);
    Estimate ab, ba;
    for (int i = 0; i < 50000; ++i) {
        const Vec3f jitter{float(i) * 1e-9f, 0.0f, 0.0f};
        ab.add(bsdf.eval(a, b + jitter, true).r);
        ba.add(bsdf.eval(b, a + jitter, true).r);
    }
    EXPECT_TRUE(test::withinSigmas(ab.mean(), ba.mean(), std::hypot(ab.standardError(), ba.standardError())));
    // Seen from below, the coat is on top all the same: the same walks.
    EXPECT_EQ(bsdf.eval(-a, -b, true), bsdf.eval(a, b, true));
    EXPECT_EQ(bsdf.pdf(-a, -b, true), bsdf.pdf(a, b, true));
    EXPECT_EQ(bsdf.eval(a, -b, true), Rgb(0.0f));  // the base is opaque
    const std::optional<BsdfSample> s = bsdf.sample(-a, 0.7f, {0.3f, 0.8f}, false);
    ASSERT_TRUE(s);
    EXPECT_LT(s->wi.z, 0.0f);
}

TEST(LayeredBsdf, ClearCoatOfIndexOneIsItsBase) {
    LayeredBsdf bsdf = coatedDiffuse(0.4f, 1.0f);
    for (const float theta : {0.0f, 60.0f}) {
        const Estimate e = sampledAlbedo(bsdf, direction(theta), 0, 100000, 41);
        EXPECT_NEAR(e.mean(), 0.4, 1e-6);  // every walk: in, one bounce, out
        EXPECT_NEAR(bsdf.eval(direction(theta), direction(30.0f, 90.0f), true).r, 0.4 / kPiD, 1e-6);
    }
}

}  // namespace
}  // namespace penumbra
