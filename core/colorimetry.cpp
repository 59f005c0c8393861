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

Xyz linearSrgbToXyz(Rgb c) {
    return {0.4124564 * c.r + 0.3575761 * c.g + 0.1804375 * c.b,
            0.2126729 * c.r + 0.7151522 * c.g + 0.0721750 * c.b,
            0.0193339 * c.r + 0.1191920 * c.g + 0.9503041 * c.b};
}

std::array<double, 2> daylightChromaticity(double kelvin) {
    const double t = kelvin * 1.4388 / 1.4380;
    if (!(t >= 4000.0)) {
        // The Planckian locus by Kim, Kim and Lee's cubics (2002, "Design of advanced color
        // temperature control system for HDTV applications"; within about 5e-4 of the locus from
        // 1667 K, clamped below): integrating Planck's law with the matching functions' fit errs by
        // 1e-3 here, which a white balance to 3000 K turns into 5% of red.
        const double v = 1.0 / std::max(t, 1667.0);
        const double x = ((-0.2661239e9 * v - 0.2343589e6) * v + 0.8776956e3) * v + 0.179910;
        const double y = t <= 2222.0 ? ((-1.1063814 * x - 1.34811020) * x + 2.18555832) * x - 0.20219683
                                     : ((-0.9549476 * x - 1.37418593) * x + 2.09137015) * x - 0.16748867;
        return {x, y};
    }
    const double u = 1.0 / std::min(t, 25000.0);
    const double x = t <= 7000.0 ? ((-4.6070e9 * u + 2.9678e6) * u + 0.09911e3) * u + 0.244063
                                 : ((-2.0064e9 * u + 1.9018e6) * u + 0.24748e3) * u + 0.237040;
    return {x, -3.0 * x * x + 2.870 * x - 0.275};
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

std::array<Xyz, 3> whiteBalanceXyz(std::array<double, 2> from, std::array<double, 2> to) {
    auto whiteCones = [](std::array<double, 2> xy) {
        return times(kBradford, {xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]});
    };
    const Xyz source = whiteCones(from), target = whiteCones(to);
    // Bradford^-1 diag(target / source) Bradford, column by column.
    std::array<Xyz, 3> m{};
    for (int column = 0; column < 3; ++column) {
        Xyz unit{};
        unit[column] = 1.0;
        Xyz cones = times(kBradford, unit);
        for (int i = 0; i < 3; ++i) cones[i] *= target[i] / source[i];
        const Xyz out = times(kBradfordInverse, cones);
        for (int row = 0; row < 3; ++row) m[row][column] = out[row];
    }
    return m;
}

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
