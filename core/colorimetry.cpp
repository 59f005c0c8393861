#include "core/colorimetry.h"

#include <algorithm>
#include <array>
#include <vector>

namespace penumbra {

namespace {

double lobe(double lambda, double mu, double sigmaBelow, double sigmaAbove) {
    const double t = (lambda - mu) / (lambda < mu ? sigmaBelow : sigmaAbove);
    return std::exp(-0.5 * t * t);
}

// Wien's displacement constant, m K.
constexpr double kWien = 2.8977721e-3;

}  // namespace

Xyz cieMatching(double lambda) {
    const double x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7) -
                     0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    const double y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    const double z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    return {x, y, z};
}

const std::vector<Xyz>& cieMatchingAt1nm() {
    static const std::vector<Xyz> table = [] {
        std::vector<Xyz> t;
        for (double lambda = kVisibleLambdaMin; lambda <= kVisibleLambdaMax; lambda += 1.0)
            t.push_back(cieMatching(lambda));
        return t;
    }();
    return table;
}

double cieYIntegral() {
    static const double integral = [] {
        double sum = 0.0;
        for (const Xyz& m : cieMatchingAt1nm()) sum += m[1];
        return sum;
    }();
    return integral;
}

Rgb xyzToLinearSrgb(const Xyz& xyz) {
    const double r = 3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2];
    const double g = -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2];
    const double b = 0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2];
    return {float(r), float(g), float(b)};
}

Rgb unitLuminanceLinearSrgb(const Xyz& xyz) {
    if (!(xyz[1] > 0.0)) return Rgb(0.0f);
    return xyzToLinearSrgb({xyz[0] / xyz[1], 1.0, xyz[2] / xyz[1]});
}

namespace {

using Matrix3 = std::array<std::array<double, 3>, 3>;

Xyz times(const Matrix3& m, const Xyz& v) {
    Xyz out{};
    for (int i = 0; i < 3; ++i) out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
    return out;
}

// XYZ to the Bradford cone responses, and back (the inverse as published with it).
constexpr Matrix3 kBradford{
    {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
constexpr Matrix3 kBradfordInverse{{{0.9869929, -0.1470543, 0.1599627},
                                    {0.4323053, 0.5183603, 0.0492912},
                                    {-0.0085287, 0.0400428, 0.9684867}}};

Xyz adaptEqualEnergyToD65(const Xyz& xyz) {
    static const Xyz equalEnergyCones = times(kBradford, spectrumToXyz([](double) { return 1.0; }));
    static const Xyz d65Cones = times(kBradford, {0.95047, 1.0, 1.08883});
    Xyz cones = times(kBradford, xyz);
    for (int i = 0; i < 3; ++i) cones[i] *= d65Cones[i] / equalEnergyCones[i];
    return times(kBradfordInverse, cones);
}

}  // namespace

Rgb reflectanceXyzToLinearSrgb(const Xyz& xyzUnderEqualEnergy) {
    // The transforms above map white to (1, 1, 1) within their published digits; the division makes it exact.
    static const Rgb white =
        xyzToLinearSrgb(adaptEqualEnergyToD65(spectrumToXyz([](double) { return 1.0; })));
    const Rgb c = xyzToLinearSrgb(adaptEqualEnergyToD65(xyzUnderEqualEnergy));
    return {c.r / white.r, c.g / white.g, c.b / white.b};
}

double planckRadiance(double lambdaNm, double kelvin) {
    constexpr double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    const double l = lambdaNm * 1e-9;
    return (2.0 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1.0));
}

Rgb blackbodyRgb(double kelvin) {
    if (!(kelvin > 0.0)) return Rgb(0.0f);
    return unitLuminanceLinearSrgb(spectrumToXyz([&](double l) { return planckRadiance(l, kelvin); }));
}

Rgb blackbodyPeakNormalizedRgb(double kelvin) {
    if (!(kelvin > 0.0)) return Rgb(0.0f);
    const double peak = planckRadiance(kWien / kelvin * 1e9, kelvin);
    return xyzToLinearSrgb(spectrumToXyz([&](double l) { return planckRadiance(l, kelvin) / peak; }));
}

Rgb blackbodyPeakNormalizedRgbTabulated(float kelvin) {
    // Steps of 1/800 in ln T: the colour changes by about (24000 K / T) / 800 of itself per step
    // (Wien's approximation at 600 nm), so linear interpolation errs by under 1e-4 of the value
    // from 1000 K up, and far below visible light's scale under it.
    constexpr double kLnMin = 4.605170185988092 /* ln 100 */, kLnMax = 13.815510557964274 /* ln 1e6 */;
    constexpr double kStepsPerLn = 800.0;
    static const std::vector<Rgb> table = [] {
        const int n = int((kLnMax - kLnMin) * kStepsPerLn) + 2;
        std::vector<Rgb> t(size_t(n), Rgb(0.0f));
        for (int i = 0; i < n; ++i)
            t[size_t(i)] = blackbodyPeakNormalizedRgb(std::exp(kLnMin + i / kStepsPerLn));
        return t;
    }();
    if (!(kelvin > 0.0f)) return Rgb(0.0f);
    const double x =
        std::clamp((std::log(double(kelvin)) - kLnMin) * kStepsPerLn, 0.0, double(table.size() - 1));
    const size_t i = std::min(size_t(x), table.size() - 2);
    const float f = float(x - double(i));
    return table[i] * (1.0f - f) + table[i + 1] * f;
}

}  // namespace penumbra
