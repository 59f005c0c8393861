#include "cameras/lens_file.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "core/commented_numbers.h"
#include "core/error.h"
#include "core/input_file.h"

namespace penumbra {

std::vector<LensSurface> parseLensFile(std::string_view text, const std::string& fileName) {
    std::vector<float> numbers;
    std::vector<int> lines;  // the line of each number
    auto fail = [&](int atLine, const std::string& message) {
        throw InputError(SourceLocation{fileName, atLine, 0, {}}, message);
    };
    forEachWordOutsideComments(text, [&](std::string_view word, int line) {
        double value = 0.0;
        const auto [stop, error] = std::from_chars(word.data(), word.data() + word.size(), value);
        if (error != std::errc() || stop != word.data() + word.size() || !std::isfinite(value) ||
            std::abs(value) > 1e9)
            fail(line, fmt::format("expected a number (a lens surface's radius, thickness, index or "
                                   "diameter in millimetres), found \"{}\"",
                                   word.substr(0, 40)));
        if (numbers.size() == 4 * kMaxLensSurfaces)
            fail(line, fmt::format("more than {} lens surfaces", kMaxLensSurfaces));
        numbers.push_back(float(value));
        lines.push_back(line);
    });
    if (numbers.empty()) fail(0, "no lens surface: expected rows of radius, thickness, index and diameter");
    if (numbers.size() % 4 != 0)
        fail(lines.back(),
             fmt::format("the last row has {} numbers; each surface needs 4 (radius, thickness, "
                         "index, diameter)",
                         numbers.size() % 4));
    std::vector<LensSurface> surfaces;
    for (size_t row = 0; row < numbers.size(); row += 4) {
        const LensSurface s{numbers[row], numbers[row + 1], numbers[row + 2], numbers[row + 3]};
        const int at = lines[row];
        if (s.thickness < 0.0f) fail(at, fmt::format("a thickness must be >= 0, found {}", s.thickness));
        if (s.eta < 0.0f)
            fail(at, fmt::format("an index of refraction must be >= 0 (0: air), found {}", s.eta));
        if (!(s.apertureDiameter > 0.0f))
            fail(at, fmt::format("an aperture diameter must be > 0, found {}", s.apertureDiameter));
        surfaces.push_back(s);
    }
    return surfaces;
}

std::vector<LensSurface> readLensFile(const std::filesystem::path& path) {
    InputFile file(path, "lens file", uint64_t(1) << 20);
    return parseLensFile(file.readAll(), path.string());
}

}  // namespace penumbra
