// Fresnel reflectance and the specular directions (mirror reflection, Snell refraction) in the
// local shading frame (normal = +z, directions point away from the surface).
//
// `eta` is always the relative index eta_t / eta_i: the index on the far side of the interface
// over the index on the side the light comes from (the side of the direction passed in).
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <optional>

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

// Mirror direction of w about the normal +z.
inline Vec3f reflectAboutZ(Vec3f w) { return {-w.x, -w.y, w.z}; }

// Mirror direction of w about the unit normal n (a microfacet's).
inline Vec3f reflectAbout(Vec3f w, Vec3f n) { return n * (2.0f * dot(w, n)) - w; }

// Unpolarized Fresnel reflectance of a dielectric interface (the mean of the s and p
// reflectances; Born & Wolf 1.5.3). cosThetaI > 0: the incident direction is on the +z side and
// eta = eta(-z side) / eta(+z side); a negative cosine means the light arrives from the -z side and
// the relative index is inverted. Total internal reflection returns 1.
inline float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
    }
    const float sin2ThetaI = std::max(0.0f, 1.0f - cosThetaI * cosThetaI);
    const float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1.0f) return 1.0f;  // total internal reflection
    const float cosThetaT = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaT));
    const float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    const float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

// Schlick's approximation R0 + (1 - R0)(1 - cos)^5 with R0 = ((eta - 1) / (eta + 1))^2, same
// arguments as fresnelDielectric. The cosine is the one on the optically thinner side (the
// transmitted angle when leaving a denser medium), which keeps the approximation reciprocal and
// gives total internal reflection beyond the critical angle.
inline float fresnelSchlick(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
    }
    const float r0 = ((eta - 1.0f) / (eta + 1.0f)) * ((eta - 1.0f) / (eta + 1.0f));
    float cosine = cosThetaI;
    if (eta < 1.0f) {
        const float sin2ThetaT = (1.0f - cosThetaI * cosThetaI) / (eta * eta);
        if (sin2ThetaT >= 1.0f) return 1.0f;
        cosine = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaT));
    }
    const float m = 1.0f - cosine;
    return r0 + (1.0f - r0) * (m * m) * (m * m) * m;
}

// Unpolarized Fresnel reflectance of a conductor of complex index eta + i k (relative to the
// outside medium), for light arriving at cos(theta) = cosThetaI >= 0 (the same formulas as the
// dielectric case with a complex index).
inline float fresnelComplex(float cosThetaI, std::complex<float> eta) {
    using Complex = std::complex<float>;
    cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
    const float sin2ThetaI = 1.0f - cosThetaI * cosThetaI;
    const Complex sin2ThetaT = sin2ThetaI / (eta * eta);
    const Complex cosThetaT = std::sqrt(Complex(1.0f) - sin2ThetaT);
    const Complex rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    const Complex rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5f * (std::norm(rParallel) + std::norm(rPerpendicular));
}

inline Rgb fresnelComplex(float cosThetaI, Rgb eta, Rgb k) {
    return {fresnelComplex(cosThetaI, {eta.r, k.r}), fresnelComplex(cosThetaI, {eta.g, k.g}),
            fresnelComplex(cosThetaI, {eta.b, k.b})};
}

// Snell refraction of w (pointing away from the surface, on the +z side when w.z > 0) through the
// interface with relative index eta = eta_t / eta_i, where eta_i is the index on w's side. Returns
// the transmitted direction (unit, on the other side), or nothing on total internal reflection.
inline std::optional<Vec3f> refractAcrossZ(Vec3f w, float eta) {
    const float n = w.z >= 0.0f ? 1.0f : -1.0f;  // the normal's sign on w's side
    const float cosThetaI = std::abs(w.z);
    const float sin2ThetaI = std::max(0.0f, 1.0f - cosThetaI * cosThetaI);
    const float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1.0f) return std::nullopt;
    const float cosThetaT = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaT));
    // wt = -w / eta + (cos_i / eta - cos_t) n (pbrt-v4's Refract), with n on w's side.
    const Vec3f wt = -w / eta + Vec3f{0.0f, 0.0f, n * (cosThetaI / eta - cosThetaT)};
    return normalize(wt);
}

// Snell refraction of w through a microfacet of unit normal n on w's side (dot(w, n) > 0), with
// eta = eta_t / eta_i relative to w's side: the transmitted direction, or nothing on total
// internal reflection.
inline std::optional<Vec3f> refractAbout(Vec3f w, Vec3f n, float eta) {
    const float cosThetaI = dot(w, n);
    const float sin2ThetaT = std::max(0.0f, 1.0f - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1.0f) return std::nullopt;
    const float cosThetaT = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaT));
    return normalize(-w / eta + n * (cosThetaI / eta - cosThetaT));
}

// The hemispherical average of fresnelDielectric for light arriving from the side of relative
// index eta (eta_t / eta_i), weighted by the cosine: 2 * integral over [0, 1] of F(mu) mu d mu,
// the fraction of diffuse light the interface reflects. Below the critical cosine mu_c (light
// from the denser side) F = 1 and the integral is mu_c^2; above it F has a square-root kink at
// mu_c, which the substitution mu = mu_c + (1 - mu_c) s^2 smooths for Simpson's rule (2048
// intervals in double).
inline double diffuseFresnelReflectance(double eta) {
    const double muCritical = eta < 1.0 ? std::sqrt(1.0 - eta * eta) : 0.0;
    const double span = 1.0 - muCritical;
    auto f = [&](double s) {
        const double mu = muCritical + span * s * s;
        return double(fresnelDielectric(float(mu), float(eta))) * mu * 2.0 * span * s;
    };
    constexpr int kIntervals = 2048;
    double sum = f(0.0) + f(1.0);
    for (int i = 1; i < kIntervals; ++i) sum += f(double(i) / kIntervals) * (i % 2 ? 4.0 : 2.0);
    return muCritical * muCritical + 2.0 * sum / (3.0 * kIntervals);
}

}  // namespace penumbra
