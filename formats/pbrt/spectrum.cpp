#include "formats/pbrt/spectrum.h"

#include <array>
#include <cmath>

namespace penumbra::pbrt {

namespace {

constexpr double kLambdaMin = 360.0, kLambdaMax = 830.0;

double lobe(double lambda, double mu, double sigmaBelow, double sigmaAbove) {
    const double t = (lambda - mu) / (lambda < mu ? sigmaBelow : sigmaAbove);
    return std::exp(-0.5 * t * t);
}

// CIE 1931 2-degree colour matching functions, Wyman, Sloan and Shirley's multi-lobe fit (JCGT 2013).
std::array<double, 3> cmf(double lambda) {
    const double x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7) -
                     0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    const double y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    const double z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    return {x, y, z};
}

Rgb xyzToRgb(const std::array<double, 3>& xyz) {
    const double r = 3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2];
    const double g = -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2];
    const double b = 0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2];
    return {float(r), float(g), float(b)};
}

double planck(double lambdaNm, double kelvin) {
    constexpr double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    const double l = lambdaNm * 1e-9;
    return (2.0 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1.0));
}

template <typename Spectrum>
std::array<double, 3> integrateXyz(const Spectrum& s) {
    std::array<double, 3> xyz{};
    for (double lambda = kLambdaMin; lambda <= kLambdaMax; lambda += 1.0) {
        const double v = s(lambda);
        const auto m = cmf(lambda);
        for (int i = 0; i < 3; ++i) xyz[i] += v * m[i];
    }
    return xyz;
}

Rgb normalizedToLuminance(const std::array<double, 3>& xyz) {
    if (!(xyz[1] > 0.0)) return Rgb(0.0f);
    return xyzToRgb({xyz[0] / xyz[1], 1.0, xyz[2] / xyz[1]});
}

double piecewiseLinear(const std::vector<double>& pairs, double lambda) {
    const size_t n = pairs.size() / 2;
    if (n == 0) return 0.0;
    if (lambda <= pairs[0]) return pairs[1];
    for (size_t i = 0; i + 1 < n; ++i) {
        const double l0 = pairs[2 * i], l1 = pairs[2 * i + 2];
        if (lambda <= l1) {
            const double t = l1 > l0 ? (lambda - l0) / (l1 - l0) : 0.0;
            return pairs[2 * i + 1] * (1.0 - t) + pairs[2 * i + 3] * t;
        }
    }
    return pairs[2 * n - 1];
}

}  // namespace

Rgb blackbodyRgb(double kelvin) {
    if (!(kelvin > 0.0)) return Rgb(0.0f);
    return normalizedToLuminance(integrateXyz([&](double l) { return planck(l, kelvin); }));
}

Rgb emissionSpectrumRgb(const std::vector<double>& pairs) {
    return normalizedToLuminance(integrateXyz([&](double l) { return piecewiseLinear(pairs, l); }));
}

Rgb reflectanceSpectrumRgb(const std::vector<double>& pairs) {
    constexpr double kWhite = 6504.0;
    const Rgb lit =
        xyzToRgb(integrateXyz([&](double l) { return piecewiseLinear(pairs, l) * planck(l, kWhite); }));
    const Rgb white = xyzToRgb(integrateXyz([&](double l) { return planck(l, kWhite); }));
    return {lit.r / white.r, lit.g / white.g, lit.b / white.b};
}

std::optional<Rgb> namedSpectrumRgb(std::string_view name) {
    struct Named {
        std::string_view name;
        Rgb rgb;
    };
    static const std::array<Named, 13> kNamed{{
        {"metal-Cu-eta", {0.200438f, 0.924033f, 1.102212f}},
        {"metal-Cu-k", {3.912949f, 2.452848f, 2.142188f}},
        {"metal-Au-eta", {0.143119f, 0.374957f, 1.442479f}},
        {"metal-Au-k", {3.983160f, 2.385721f, 1.603215f}},
        {"metal-Ag-eta", {0.155265f, 0.116723f, 0.138342f}},
        {"metal-Ag-k", {4.828180f, 3.122250f, 2.146960f}},
        {"metal-Al-eta", {1.657460f, 0.880369f, 0.521229f}},
        {"metal-Al-k", {9.223869f, 6.269523f, 4.837001f}},
        {"glass-BK7", Rgb(1.5168f)},
        {"glass-BAF10", Rgb(1.6700f)},
        {"glass-FK51A", Rgb(1.4866f)},
        {"glass-LASF9", Rgb(1.8503f)},
        {"glass-F5", Rgb(1.6034f)},
    }};
    for (const Named& n : kNamed)
        if (n.name == name) return n.rgb;
    if (name == "stdillum-D65") return Rgb(1.0f);
    if (name == "stdillum-A") return blackbodyRgb(2856.0);
    return std::nullopt;
}

}  // namespace penumbra::pbrt
