// Scattering from a hair fiber: the model of Chiang, Bitterli, Tappan and Burley ("A Practical and
// Controllable Hair and Fur Model for Production Path Tracing", EGSR 2016), built on d'Eon, Francois,
// Hill, Letteri and Aubry ("An Energy-Conserving Hair Reflectance Model", EGSR 2011), as pbrt-v4's
// `hair` material uses it. The fiber is a dielectric cylinder of index `eta` with an absorbing
// interior (sigma_a, per unit of the fiber's diameter); light leaves it after p = 0 (reflection, R),
// 1 (transmission, TT), 2 (TRT) or more internal paths, each lobe the product of
//   Mp  a longitudinal lobe about the specular cone, of variance v_p (from beta_m), tilted by the
//       cuticle scales' angle alpha (R by -2 alpha, TT by alpha, TRT by 4 alpha),
//   Ap  the fraction of light that takes that path: Fresnel at the surface, Beer-Lambert inside,
//   Np  an azimuthal lobe, a logistic of scale s (from beta_n) about the deflection of a ray
//       entering at offset h, trimmed to [-pi, pi];
// the paths of p >= 3 summed in closed form into one lobe, uniform in azimuth.
//
// Coordinates are the fiber's: x runs along it, so sin(theta) = w.x; the azimuth phi is measured in
// the yz plane, atan2(w.z, w.y); h in [-1, 1] is where across the fiber's width the ray arrived
// (a curve's v maps to h = 2 v - 1). Mp is normalized over the sphere for cos(theta_i) d theta_i
// and Np over phi, so the sum over lobes of Ap is the fiber's albedo: with sigma_a = 0 every ray
// leaves it (the white furnace test).
//
// eval() returns f, whose product with |w_i.z| (the renderer's cosine) is the sum of the lobes; a
// hair BSDF scatters over the whole sphere, so it is both a reflection and a transmission.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/trig.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/fresnel.h"

namespace penumbra {

namespace hair {

inline constexpr int kPMax = 3;  // lobes p = 0, 1, 2 explicitly, then p >= 3 as one
// The modified Bessel function of the first kind of order 0, by its series, and its logarithm
// (an asymptotic form beyond x = 12). 24 terms leave a relative error below 1e-6 up to x = 12;
// the 10 of pbrt-v4 leave 2% there (a grazing ray's lobe at small beta_m).
inline float besselI0(float x) {
    float value = 0.0f, term = 1.0f;  // term i: (x^2 / 4)^i / (i!)^2
    const float quarterX2 = 0.25f * x * x;
    for (int i = 0; i < 24; ++i) {
        value += term;
        term *= quarterX2 / float((i + 1) * (i + 1));
    }
    return value;
}
inline float logBesselI0(float x) {
    if (x > 12.0f) return x + 0.5f * (-std::log(2.0f * kPi) + std::log(1.0f / x) + 1.0f / (8.0f * x));
    return std::log(besselI0(x));
}

// The longitudinal lobe of variance v (d'Eon et al. 2011), in log space for small v where the Bessel
// function and the hyperbolic sine both overflow.
inline float mp(float cosThetaI, float cosThetaO, float sinThetaI, float sinThetaO, float v) {
    const float a = cosThetaI * cosThetaO / v, b = sinThetaI * sinThetaO / v;
    if (v <= 0.1f) return std::exp(logBesselI0(a) - b - 1.0f / v + 0.6931f + std::log(1.0f / (2.0f * v)));
    return std::exp(-b) * besselI0(a) / (std::sinh(1.0f / v) * 2.0f * v);
}

// The azimuthal deflection of lobe p for a ray entering at gamma_o and refracted to gamma_t.
inline float phi(int p, float gammaO, float gammaT) {
    return 2.0f * float(p) * gammaT - 2.0f * gammaO + float(p) * kPi;
}

inline float logistic(float x, float s) {
    x = std::abs(x);
    const float e = std::exp(-x / s);
    return e / (s * (1.0f + e) * (1.0f + e));
}
inline float logisticCdf(float x, float s) { return 1.0f / (1.0f + std::exp(-x / s)); }
inline float trimmedLogistic(float x, float s, float a, float b) {
    return logistic(x, s) / (logisticCdf(b, s) - logisticCdf(a, s));
}
// A sample of the logistic trimmed to [a, b] by inverting its CDF.
inline float sampleTrimmedLogistic(float u, float s, float a, float b) {
    const float k = logisticCdf(b, s) - logisticCdf(a, s);
    const float x = -s * std::log(1.0f / (u * k + logisticCdf(a, s)) - 1.0f);
    return std::clamp(x, a, b);
}

// The azimuthal lobe p at azimuth difference phiDifference.
inline float np(float phiDifference, int p, float s, float gammaO, float gammaT) {
    float d = phiDifference - phi(p, gammaO, gammaT);
    // Into [-pi, pi]: the lobe's deflection may have wrapped around the fiber several times.
    d = std::remainder(d, 2.0f * kPi);
    return trimmedLogistic(d, s, -kPi, kPi);
}

}  // namespace hair

struct HairBsdf {
    float h = 0.0f;             // where across the fiber the ray arrived, in [-1, 1]
    float eta = 1.55f;          // the fiber's index of refraction
    Rgb sigmaA{0, 0, 0};        // absorption per unit of the fiber's diameter
    float betaM = 0.3f;         // longitudinal roughness, in [0, 1]
    float betaN = 0.3f;         // azimuthal roughness, in [0, 1]
    float alphaDegrees = 2.0f;  // the cuticle scales' tilt

    static constexpr BsdfFlags kFlags = BsdfFlags::Glossy | BsdfFlags::Reflection | BsdfFlags::Transmission;

    // pbrt-v4's and Chiang et al.'s parameterizations of sigma_a: melanin concentrations (eumelanin
    // makes hair black to brown, pheomelanin red), with the pigments' absorption coefficients
    // measured by Donner et al. 2008, and the inversion of a desired diffuse colour (Chiang et
    // al. 2016, eq. 9, fitted for the azimuthal roughness betaN).
    static Rgb sigmaAFromConcentration(float eumelanin, float pheomelanin) {
        const Rgb eumelaninSigmaA{0.419f, 0.697f, 1.37f}, pheomelaninSigmaA{0.187f, 0.4f, 1.05f};
        return eumelaninSigmaA * eumelanin + pheomelaninSigmaA * pheomelanin;
    }
    static Rgb sigmaAFromReflectance(Rgb c, float betaN) {
        const float b = betaN, b2 = b * b, b3 = b2 * b, b4 = b3 * b, b5 = b4 * b;
        const float denominator = 5.969f - 0.215f * b + 2.532f * b2 - 10.73f * b3 + 5.574f * b4 + 0.245f * b5;
        float sigma[3];
        for (int i = 0; i < 3; ++i) {
            const float l = std::log(std::max(c[i], 1e-6f)) / denominator;
            sigma[i] = l * l;
        }
        return {sigma[0], sigma[1], sigma[2]};
    }

    // The quantities every evaluation shares, from the parameters.
    struct Lobes {
        std::array<float, hair::kPMax + 1> v;  // Mp's variance per lobe
        float s;                               // Np's logistic scale
        float sin2kAlpha[3], cos2kAlpha[3];    // sin and cos of 2^k alpha, k = 0, 1, 2
        float gammaO;
    };
    Lobes lobes() const {
        Lobes l;
        const float bm = betaM, bn = betaN;
        const float v0 = 0.726f * bm + 0.812f * bm * bm + 3.7f * std::pow(bm, 20.0f);
        l.v[0] = v0 * v0;
        l.v[1] = 0.25f * l.v[0];
        l.v[2] = 4.0f * l.v[0];
        for (int p = 3; p <= hair::kPMax; ++p) l.v[p] = l.v[2];
        l.s = std::sqrt(kPi / 8.0f) * (0.265f * bn + 1.194f * bn * bn + 5.372f * std::pow(bn, 22.0f));
        l.sin2kAlpha[0] = std::sin(alphaDegrees * kPi / 180.0f);
        l.cos2kAlpha[0] = safeSqrt(1.0f - l.sin2kAlpha[0] * l.sin2kAlpha[0]);
        for (int i = 1; i < 3; ++i) {
            l.sin2kAlpha[i] = 2.0f * l.cos2kAlpha[i - 1] * l.sin2kAlpha[i - 1];
            l.cos2kAlpha[i] =
                l.cos2kAlpha[i - 1] * l.cos2kAlpha[i - 1] - l.sin2kAlpha[i - 1] * l.sin2kAlpha[i - 1];
        }
        l.gammaO = safeAsin(h);
        return l;
    }

    // Ap for each lobe, the light leaving by it, for a ray of longitudinal angle theta_o.
    std::array<Rgb, hair::kPMax + 1> attenuation(float sinThetaO, float cosThetaO) const {
        // The refracted ray's longitudinal and azimuthal angles.
        const float sinThetaT = sinThetaO / eta, cosThetaT = safeSqrt(1.0f - sinThetaT * sinThetaT);
        const float cosGammaT = std::cos(gammaTOf(sinThetaO, cosThetaO));
        // Transmittance across the fiber once: the path length 2 cos(gamma_t) / cos(theta_t) diameters.
        const float pathLength = 2.0f * cosGammaT / std::max(cosThetaT, 1e-6f);
        const Rgb transmittance{std::exp(-sigmaA.r * pathLength), std::exp(-sigmaA.g * pathLength),
                                std::exp(-sigmaA.b * pathLength)};
        const float cosGammaO = safeSqrt(1.0f - h * h);
        const float f = fresnelDielectric(cosThetaO * cosGammaO, eta);
        std::array<Rgb, hair::kPMax + 1> ap;
        ap[0] = Rgb(f);
        ap[1] = transmittance * ((1.0f - f) * (1.0f - f));
        for (int p = 2; p < hair::kPMax; ++p) ap[p] = ap[p - 1] * transmittance * f;
        // The rest, p >= kPMax, a geometric series.
        const Rgb tf = transmittance * f;
        ap[hair::kPMax] =
            Rgb(ap[hair::kPMax - 1].r * tf.r / (1.0f - tf.r), ap[hair::kPMax - 1].g * tf.g / (1.0f - tf.g),
                ap[hair::kPMax - 1].b * tf.b / (1.0f - tf.b));
        return ap;
    }

    // Lobe p's theta_o, turned by the scales' tilt: R by -2 alpha, TT by alpha, TRT by 4 alpha.
    static void tiltedThetaO(const Lobes& l, int p, float sinThetaO, float cosThetaO, float& sinOut,
                             float& cosOut) {
        switch (p) {
            case 0:
                sinOut = sinThetaO * l.cos2kAlpha[1] - cosThetaO * l.sin2kAlpha[1];
                cosOut = cosThetaO * l.cos2kAlpha[1] + sinThetaO * l.sin2kAlpha[1];
                break;
            case 1:
                sinOut = sinThetaO * l.cos2kAlpha[0] + cosThetaO * l.sin2kAlpha[0];
                cosOut = cosThetaO * l.cos2kAlpha[0] - sinThetaO * l.sin2kAlpha[0];
                break;
            case 2:
                sinOut = sinThetaO * l.cos2kAlpha[2] + cosThetaO * l.sin2kAlpha[2];
                cosOut = cosThetaO * l.cos2kAlpha[2] - sinThetaO * l.sin2kAlpha[2];
                break;
            default:
                sinOut = sinThetaO;
                cosOut = cosThetaO;
                break;
        }
        cosOut = std::abs(cosOut);
    }

    // The lobes' share of the light leaving along wo (their Ap), the probability of sampling each.
    static std::array<float, hair::kPMax + 1> lobeProbabilities(const std::array<Rgb, hair::kPMax + 1>& ap) {
        std::array<float, hair::kPMax + 1> pdf;
        float sum = 0.0f;
        for (int p = 0; p <= hair::kPMax; ++p) sum += pdf[p] = (ap[p].r + ap[p].g + ap[p].b) / 3.0f;
        for (float& x : pdf) x = sum > 0.0f ? x / sum : 1.0f / float(hair::kPMax + 1);
        return pdf;
    }

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const { return evaluate(wo, wi).f; }
    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const { return evaluate(wo, wi).pdf; }

    // A lobe chosen with uLobe by its share of the light (the rest of uLobe then samples its
    // azimuth), theta_i from its Mp with u, phi from its Np: the density is pdf(), the sum over
    // lobes, so the sample agrees with eval() and pdf() as multiple importance sampling needs.
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool /*front*/) const {
        const Lobes l = lobes();
        const float sinThetaO = wo.x, cosThetaO = safeSqrt(1.0f - sinThetaO * sinThetaO);
        const float phiO = std::atan2(wo.z, wo.y);
        const std::array<float, hair::kPMax + 1> lobePdf =
            lobeProbabilities(attenuation(sinThetaO, cosThetaO));
        int p = 0;
        float remapped = uLobe;
        for (; p < hair::kPMax; ++p) {
            if (remapped < lobePdf[p]) break;
            remapped -= lobePdf[p];
        }
        remapped = std::min(remapped / std::max(lobePdf[p], 1e-12f), 0x1.fffffep-1f);
        float sinO, cosO;
        tiltedThetaO(l, p, sinThetaO, cosThetaO, sinO, cosO);
        // theta_i from Mp (d'Eon et al.'s inversion, in the form that stays finite for small v).
        const float u0 = std::max(u.x, 1e-5f);
        const float cosTheta = 1.0f + l.v[p] * std::log(u0 + (1.0f - u0) * std::exp(-2.0f / l.v[p]));
        const float sinTheta = safeSqrt(1.0f - cosTheta * cosTheta);
        const float cosPhi = std::cos(2.0f * kPi * u.y);
        const float sinThetaI = std::clamp(-cosTheta * sinO + sinTheta * cosPhi * cosO, -1.0f, 1.0f);
        const float cosThetaI = safeSqrt(1.0f - sinThetaI * sinThetaI);
        // phi_i from Np, or uniformly for the closed-form lobe.
        const float gammaT = gammaTOf(sinThetaO, cosThetaO);
        const float dPhi = p < hair::kPMax ? hair::phi(p, l.gammaO, gammaT) +
                                                 hair::sampleTrimmedLogistic(remapped, l.s, -kPi, kPi)
                                           : 2.0f * kPi * remapped;
        const float phiI = phiO + dPhi;
        const Vec3f wi{sinThetaI, cosThetaI * std::cos(phiI), cosThetaI * std::sin(phiI)};
        const Evaluation at = evaluate(wo, wi);
        const float density = at.pdf;
        if (!(density > 0.0f)) return std::nullopt;
        const Rgb weight = at.f * (std::abs(wi.z) / density);
        const BsdfFlags direction = wo.z * wi.z > 0.0f ? BsdfFlags::Reflection : BsdfFlags::Transmission;
        return BsdfSample{wi, weight, density, BsdfFlags::Glossy | direction};
    }

    // The light the fiber sends back in all its lobes at normal incidence, for the albedo AOV.
    Rgb reflectanceForAov() const {
        const std::array<Rgb, hair::kPMax + 1> ap = attenuation(0.0f, 1.0f);
        return ap[0] + ap[1] + ap[2] + ap[3];
    }

private:
    // f and the pdf of the pair (wo, wi): the same lobes summed with Ap for f and with the lobes'
    // sampling probabilities for the pdf, in one pass.
    struct Evaluation {
        Rgb f;
        float pdf;
    };
    Evaluation evaluate(Vec3f wo, Vec3f wi) const {
        const Lobes l = lobes();
        const float sinThetaO = wo.x, cosThetaO = safeSqrt(1.0f - sinThetaO * sinThetaO);
        const float sinThetaI = wi.x, cosThetaI = safeSqrt(1.0f - sinThetaI * sinThetaI);
        const float dPhi = std::atan2(wi.z, wi.y) - std::atan2(wo.z, wo.y);
        const float gammaT = gammaTOf(sinThetaO, cosThetaO);
        const std::array<Rgb, hair::kPMax + 1> ap = attenuation(sinThetaO, cosThetaO);
        const std::array<float, hair::kPMax + 1> lobePdf = lobeProbabilities(ap);
        Rgb f(0.0f);
        float pdf = 0.0f;
        for (int p = 0; p < hair::kPMax; ++p) {
            float sinO, cosO;
            tiltedThetaO(l, p, sinThetaO, cosThetaO, sinO, cosO);
            const float m = hair::mp(cosThetaI, cosO, sinThetaI, sinO, l.v[p]);
            const float n = hair::np(dPhi, p, l.s, l.gammaO, gammaT);
            f += ap[p] * (m * n);
            pdf += m * lobePdf[p] * n;
        }
        const float m = hair::mp(cosThetaI, cosThetaO, sinThetaI, sinThetaO, l.v[hair::kPMax]);
        f += ap[hair::kPMax] * (m / (2.0f * kPi));
        pdf += m * lobePdf[hair::kPMax] / (2.0f * kPi);
        const float cosine = std::abs(wi.z);
        return {cosine > 0.0f ? f / cosine : Rgb(0.0f), pdf};
    }

    // gamma_t: the refracted ray's azimuthal angle inside the fiber (Bravais' modified index).
    float gammaTOf(float sinThetaO, float cosThetaO) const {
        const float etaP =
            std::sqrt(std::max(0.0f, eta * eta - sinThetaO * sinThetaO)) / std::max(cosThetaO, 1e-6f);
        return safeAsin(h / etaP);
    }
};

}  // namespace penumbra
