// Shared machinery of the material tests: building materials, a partition of the sphere of
// directions into cells, adaptive cubature of a density over those cells (the expected counts of
// the chi-square tests), and independent one-dimensional integrals of the Phong lobe.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/frame.h"
#include "core/vec.h"
#include "materials/material.h"

namespace penumbra::test {

inline constexpr double kPiD = std::numbers::pi;

inline double radians(double degrees) { return degrees * kPiD / 180.0; }

// Unit direction at polar angle theta (from +z) and azimuth phi, in degrees.
inline Vec3f directionFromAngles(double thetaDegrees, double phiDegrees) {
    const double t = radians(thetaDegrees), p = radians(phiDegrees);
    return {float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t))};
}

inline Material makeLambertMaterial(Rgb albedo) { return Material(Lambert{albedo}); }

inline Material makePhongMaterial(Rgb kd, Rgb ks, float exponent) {
    return Material(Phong{kd, ks, exponent});
}

inline Material makeDielectricMaterial(float eta, FresnelModel fresnel = FresnelModel::Exact) {
    Dielectric dielectric;
    dielectric.eta = eta;
    dielectric.fresnel = fresnel;
    return Material(dielectric);
}

inline Material makeThinDielectricMaterial(float eta) {
    ThinDielectric thin;
    thin.eta = eta;
    return Material(thin);
}

// The material's Phong model, or null when it is another.
inline const Phong* phongOf(const Material& m) { return std::get_if<Phong>(&m.model()); }

// The sphere of directions cut into thetaBins x phiBins cells around the polar axis frame.n.
// Rings are equal steps of t in [0, 1], where 1 - cos(theta) = 2 t^gamma: gamma = 1 gives rings
// of equal solid angle, larger gamma makes the rings near the axis finer, which resolves narrow
// lobes centred on it. The cells partition the sphere, so any choice is a valid chi-square test.
struct SphereBinning {
    Frame frame = Frame::fromNormal({0.0f, 0.0f, 1.0f});
    int thetaBins = 20;
    int phiBins = 40;
    double gamma = 1.0;

    int cellCount() const { return thetaBins * phiBins; }

    int cellOf(Vec3f w) const {
        const Vec3f local = frame.toLocal(w);
        const double c = std::clamp(double(local.z) / std::sqrt(double(lengthSquared(local))), -1.0, 1.0);
        const double t = std::pow(std::max(0.0, 0.5 * (1.0 - c)), 1.0 / gamma);
        const int i = std::min(int(t * thetaBins), thetaBins - 1);
        double phi = std::atan2(double(local.y), double(local.x));
        if (phi < 0.0) phi += 2.0 * kPiD;
        const int j = std::min(int(phi / (2.0 * kPiD) * phiBins), phiBins - 1);
        return i * phiBins + j;
    }

    Vec3f direction(double t, double phi) const {
        const double c = 1.0 - 2.0 * std::pow(t, gamma);
        const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
        return frame.toWorld({float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)});
    }
    // Solid angle per unit t and phi: |d cos(theta) / dt| = 2 gamma t^(gamma - 1).
    double jacobian(double t) const { return 2.0 * gamma * std::pow(t, gamma - 1.0); }
};

// Adaptive cubature over a rectangle: a 4 x 4 Gauss-Legendre rule on the rectangle is compared
// with the same rule on its four quarters, and quarters are refined until the two agree within
// max(absoluteTolerance, relativeTolerance * |value|) or `maxDepth` levels are used. Refinement is
// what makes the cells that a discontinuity crosses (the horizon, where a density drops to 0)
// accurate: each level halves their error. The relative tolerance keeps the refinement from
// chasing the float rounding noise of the integrand (a float pdf of exponent n carries relative
// noise of about n * 1e-7). `errorEstimate` accumulates |coarse - fine| of the accepted pieces.
template <typename F>
class AdaptiveCubature {
public:
    AdaptiveCubature(const F& f, double absoluteTolerance, double relativeTolerance, int minDepth,
                     int maxDepth)
        : f_(f),
          absoluteTolerance_(absoluteTolerance),
          relativeTolerance_(relativeTolerance),
          minDepth_(minDepth),
          maxDepth_(maxDepth) {}

    double integrate(double x0, double x1, double y0, double y1) {
        return refine(x0, x1, y0, y1, gauss(x0, x1, y0, y1), maxDepth_);
    }
    double errorEstimate = 0.0;

private:
    double gauss(double x0, double x1, double y0, double y1) {
        static constexpr double kNodes[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                             0.8611363115940526};
        static constexpr double kWeights[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                               0.3478548451374538};
        const double hx = 0.5 * (x1 - x0), hy = 0.5 * (y1 - y0), mx = 0.5 * (x0 + x1), my = 0.5 * (y0 + y1);
        double sum = 0.0;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                sum += kWeights[i] * kWeights[j] * f_(mx + hx * kNodes[i], my + hy * kNodes[j]);
        return sum * hx * hy;
    }
    double refine(double x0, double x1, double y0, double y1, double whole, int depth) {
        const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
        const double q[4] = {gauss(x0, xm, y0, ym), gauss(xm, x1, y0, ym), gauss(x0, xm, ym, y1),
                             gauss(xm, x1, ym, y1)};
        const double fine = q[0] + q[1] + q[2] + q[3];
        const double difference = std::abs(fine - whole);
        const bool deepEnough = maxDepth_ - depth >= minDepth_;
        if (depth <= 0 ||
            (deepEnough && difference <= std::max(absoluteTolerance_, relativeTolerance_ * std::abs(fine)))) {
            errorEstimate += difference;
            return fine;
        }
        return refine(x0, xm, y0, ym, q[0], depth - 1) + refine(xm, x1, y0, ym, q[1], depth - 1) +
               refine(x0, xm, ym, y1, q[2], depth - 1) + refine(xm, x1, ym, y1, q[3], depth - 1);
    }

    const F& f_;
    double absoluteTolerance_, relativeTolerance_;
    int minDepth_, maxDepth_;
};

struct CellIntegrals {
    std::vector<double> value;  // per cell
    std::vector<double> error;  // estimated absolute error per cell
};

// The integral of density(w) over every cell of `binning`, each to within about
// max(absoluteTolerance, 1e-4 relative) where `maxDepth` levels of refinement reach it; cells that
// a discontinuity crosses stop at maxDepth levels, with an error about 2^-maxDepth of their
// unrefined one. Every
// cell is refined at least `minDepth` levels (2: 256 points), so that a thin sliver of a cell
// beyond a discontinuity is not missed by all the points of the coarse rules.
template <typename Density>
CellIntegrals integrateOverCells(const SphereBinning& binning, const Density& density,
                                 double absoluteTolerance, int maxDepth = 7, int minDepth = 2) {
    auto integrand = [&](double t, double phi) {
        return double(density(binning.direction(t, phi))) * binning.jacobian(t);
    };
    CellIntegrals result;
    result.value.resize(size_t(binning.cellCount()));
    result.error.resize(size_t(binning.cellCount()));
    for (int i = 0; i < binning.thetaBins; ++i)
        for (int j = 0; j < binning.phiBins; ++j) {
            AdaptiveCubature<decltype(integrand)> cubature(integrand, absoluteTolerance, 1e-4, minDepth,
                                                           maxDepth);
            const size_t cell = size_t(i * binning.phiBins + j);
            result.value[cell] =
                cubature.integrate(double(i) / binning.thetaBins, double(i + 1) / binning.thetaBins,
                                   2.0 * kPiD * j / binning.phiBins, 2.0 * kPiD * (j + 1) / binning.phiBins);
            result.error[cell] = cubature.errorEstimate;
        }
    return result;
}

// The integral of f cos over the hemisphere of wi above the surface, by the midpoint rule in
// (cos theta, phi) on a 400 x 400 grid: accurate to about 1e-4 for lobes as broad as GGX of alpha 0.3.
inline Rgb directionalAlbedo(const Material& material, Vec3f wo) {
    Rgb sum(0.0f);
    const int n = 400;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double mu = (i + 0.5) / n, phi = 2.0 * kPiD * (j + 0.5) / n;
            const double s = std::sqrt(1.0 - mu * mu);
            const Vec3f wi{float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu)};
            sum = sum + material.eval(wo, wi, true) * float(mu);
        }
    return sum * float(2.0 * kPiD / (double(n) * n));
}

// Composite Simpson rule of f over [a, b] with n (even) intervals.
template <typename F>
double simpson(const F& f, double a, double b, int n) {
    const double h = (b - a) / n;
    double sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
    return sum * h / 3.0;
}

// Integrals over the ring of directions at angle alpha around an axis at polar angle thetaAxis
// (from +z), of the part above the horizon z > 0. On the ring, z = a + b cos(phi) with
// a = cos(alpha) cos(thetaAxis) and b = sin(alpha) sin(thetaAxis) >= 0.
//   ringAbove:   measure of {phi : z > 0}
//   ringCosine:  integral of max(0, z) d phi
inline double ringAbove(double cosAlpha, double thetaAxis) {
    const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
    const double a = cosAlpha * std::cos(thetaAxis), b = sinAlpha * std::sin(thetaAxis);
    if (b <= std::abs(a)) return a > 0.0 ? 2.0 * kPiD : 0.0;
    return 2.0 * std::acos(-a / b);
}
inline double ringCosine(double cosAlpha, double thetaAxis) {
    const double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
    const double a = cosAlpha * std::cos(thetaAxis), b = sinAlpha * std::sin(thetaAxis);
    if (b <= std::abs(a)) return a > 0.0 ? 2.0 * kPiD * a : 0.0;
    const double phi0 = std::acos(-a / b);
    return 2.0 * (a * phi0 + b * std::sin(phi0));
}

// The Phong specular lobe of exponent n around the mirror direction of a wo at polar angle
// thetaO, integrated in one dimension over the angle alpha from the lobe's axis (composite
// Simpson, 2 * 10^5 intervals over [0, pi / 2]: about 4000 across the narrowest lobe tested, and
// the only kink, where the ring first touches the horizon, costs O(h^2) ~ 1e-10):
//   phongLobeShareAbove: the fraction of the sampling density (n + 1) / (2 pi) cos^n lying above the horizon;
//   phongSpecularAlbedo: integral over the upper hemisphere of (n + 2) / (2 pi) cos^n(alpha) cos(theta_i),
//                        the specular lobe's albedo for ks = 1 (1 at normal incidence, less where the horizon
//                        clips it).
inline double phongLobeShareAbove(double exponent, double thetaO) {
    auto f = [&](double alpha) {
        return (exponent + 1.0) / (2.0 * kPiD) * std::pow(std::cos(alpha), exponent) * std::sin(alpha) *
               ringAbove(std::cos(alpha), thetaO);
    };
    return simpson(f, 0.0, kPiD / 2.0, 200000);
}
inline double phongSpecularAlbedo(double exponent, double thetaO) {
    auto f = [&](double alpha) {
        return (exponent + 2.0) / (2.0 * kPiD) * std::pow(std::cos(alpha), exponent) * std::sin(alpha) *
               ringCosine(std::cos(alpha), thetaO);
    };
    return simpson(f, 0.0, kPiD / 2.0, 200000);
}

// Fresnel reflectance of a dielectric in the angle form (Hecht, Optics, 4.42-4.43):
// r_s = -sin(ti - tt) / sin(ti + tt), r_p = tan(ti - tt) / tan(ti + tt), with Snell's law for tt;
// an independent formulation of fresnelDielectric (which works with cosines), in double.
// cosThetaI > 0, eta = eta_t / eta_i.
inline double fresnelHecht(double cosThetaI, double eta) {
    const double ti = std::acos(std::clamp(cosThetaI, -1.0, 1.0));
    const double sinT = std::sin(ti) / eta;
    if (sinT >= 1.0) return 1.0;
    const double tt = std::asin(sinT);
    if (ti < 1e-6)
        return ((eta - 1.0) / (eta + 1.0)) * ((eta - 1.0) / (eta + 1.0));  // normal incidence limit
    const double rs = -std::sin(ti - tt) / std::sin(ti + tt);
    const double rp = std::tan(ti - tt) / std::tan(ti + tt);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace penumbra::test
