#include "formats/pbrt/spectrum.h"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <string>

#include "core/colorimetry.h"
#include "core/commented_numbers.h"
#include "core/error.h"

namespace penumbra::pbrt {

namespace {

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

Rgb emissionSpectrumRgb(const std::vector<double>& pairs) {
    return unitLuminanceLinearSrgb(spectrumToXyz([&](double l) { return piecewiseLinear(pairs, l); }));
}

Rgb reflectanceSpectrumRgb(const std::vector<double>& pairs) {
    constexpr double kWhite = 6504.0;
    const Rgb lit = xyzToLinearSrgb(
        spectrumToXyz([&](double l) { return piecewiseLinear(pairs, l) * planckRadiance(l, kWhite); }));
    const Rgb white = xyzToLinearSrgb(spectrumToXyz([&](double l) { return planckRadiance(l, kWhite); }));
    return {lit.r / white.r, lit.g / white.g, lit.b / white.b};
}

std::optional<Rgb> namedSpectrumRgb(std::string_view name) {
    struct Named {
        std::string_view name;
        Rgb rgb;
    };
    static const std::array<Named, 15> kNamed{{
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
        {"glass-F5", Rgb(1.67270f)},   // SF5
        {"glass-F10", Rgb(1.72825f)},  // SF10
        {"glass-F11", Rgb(1.78472f)},  // SF11
    }};
    for (const Named& n : kNamed)
        if (n.name == name) return n.rgb;
    if (name == "stdillum-D65") return Rgb(1.0f);
    if (name == "stdillum-A") return blackbodyRgb(2856.0);
    return std::nullopt;
}

std::vector<double> parseSpectrumFile(std::string_view text, const std::string& fileName) {
    std::vector<double> pairs;
    int lastNumberLine = 1;
    const auto fail = [&](int line, const std::string& message) {
        throw InputError(SourceLocation{fileName, line, 0, {}}, message);
    };
    const int lastLine = forEachWordOutsideComments(text, [&](std::string_view word, int line) {
        double value = 0.0;
        const char* first = word.data() + (word.front() == '+' ? 1 : 0);
        const auto [stop, error] = std::from_chars(first, word.data() + word.size(), value);
        if (error != std::errc() || stop != word.data() + word.size() || !std::isfinite(value))
            fail(line, fmt::format("expected a number, found '{}'", word));
        if (pairs.size() % 2 == 0 && !pairs.empty() && !(value > pairs[pairs.size() - 2]))
            fail(line,
                 fmt::format("wavelengths must increase: {} follows {}", value, pairs[pairs.size() - 2]));
        pairs.push_back(value);
        lastNumberLine = line;
    });
    if (pairs.empty()) fail(lastLine, "a spectrum file holds (wavelength, value) pairs: this one holds none");
    if (pairs.size() % 2 != 0)  // at the line where the pair is left incomplete
        fail(lastNumberLine,
             fmt::format("a spectrum file holds (wavelength, value) pairs: this one holds {} numbers",
                         pairs.size()));
    return pairs;
}

}  // namespace penumbra::pbrt
