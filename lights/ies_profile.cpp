// The IES LM-63 reader. The layout (IESNA LM-63-1986, -1991, -1995, -2002; IES LM-63-2019):
//   an identifier line ("IESNA91", "IESNA:LM-63-1995", "IESNA:LM-63-2002", "IES:LM-63-2019";
//     none in LM-63-1986),
//   keyword lines "[TEST] ..." (free text in LM-63-1986), up to
//   TILT=NONE | TILT=INCLUDE | TILT=<file>,
//   with TILT=INCLUDE: lamp-to-luminaire geometry, number of tilt angles N, N angles, N factors,
//   number of lamps, lumens per lamp (-1: absolute photometry), candela multiplier,
//     number of vertical angles, number of horizontal angles, photometric type (1 = C, 2 = B,
//     3 = A), units type (1 = feet, 2 = metres), width, length, height of the luminous opening,
//   ballast factor, ballast-lamp photometric factor ("future use" since LM-63-2002), input watts,
//   the vertical angles, the horizontal angles, then the candela values: those of the first
//     horizontal angle at each vertical angle, then those of the second, and so on.
// After the TILT line the numbers may be separated by any whitespace and commas, and spread over
// any number of lines.
#include "lights/ies_profile.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"

namespace penumbra {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadiansPerDegree = kPi / 180.0;

[[noreturn]] void fail(std::string_view file, int line, const std::string& message) {
    throw InputError(SourceLocation{std::string(file), line, 0, ""}, message);
}

// A token for a message: at most 32 characters, unprintable bytes as '?'.
std::string quoted(std::string_view token) {
    std::string out = "'";
    for (size_t i = 0; i < std::min<size_t>(token.size(), 32); ++i)
        out += (token[i] >= 0x20 && token[i] < 0x7f) ? token[i] : '?';
    if (token.size() > 32) out += "...";
    return out + "'";
}

// A number for a message, as the file would write it.
std::string num(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", v);
    return buffer;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return s;
}

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
        if (lower(a[i]) != lower(b[i])) return false;
    }
    return true;
}

// The file's text, read line by line up to the TILT line and number by number after it. Lines end
// at "\n", "\r\n" or a lone "\r" (files written on old Macs).
class Reader {
public:
    Reader(std::string_view text, std::string_view file) : text_(text), file_(file) {}

    bool atEnd() const { return pos_ >= text_.size(); }
    int line() const { return line_; }
    std::string_view file() const { return file_; }

    // The rest of the current line, without its end; moves to the next line.
    std::string_view readLine() {
        const size_t end = std::min(text_.find_first_of("\r\n", pos_), text_.size());
        const std::string_view line = text_.substr(pos_, end - pos_);
        pos_ = end;
        if (pos_ < text_.size()) {
            pos_ += (text_[pos_] == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') ? 2 : 1;
            ++line_;
        }
        return line;
    }

    // The next number, `what` naming it for messages ("the candela multiplier").
    double number(const std::string& what) {
        const std::string_view token = nextToken();
        if (token.empty()) fail(file_, lastLine_, "expected " + what + ", found the end of the file");
        return parse(token, what);
    }

    // The next number, which must be an integer from `lo` to `hi`.
    int integer(const std::string& what, int lo, int hi) {
        const std::string_view token = nextToken();
        const std::string range =
            " (an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ")";
        if (token.empty()) fail(file_, lastLine_, "expected " + what + range + ", found the end of the file");
        const double value = parse(token, what);
        if (value != std::floor(value) || value < lo || value > hi)
            fail(file_, lastLine_, "expected " + what + range + ", found " + quoted(token));
        return int(value);
    }

    // `count` numbers ("37 vertical angles"), calling `check(value, line)` on each.
    template <typename Check>
    std::vector<double> list(int count, const std::string& what, Check check) {
        std::vector<double> values;  // grows only with the numbers the file holds
        for (int i = 0; i < count; ++i) {
            const std::string_view token = nextToken();
            if (token.empty())
                fail(file_, lastLine_,
                     "expected " + std::to_string(count) + " " + what + ", found " + std::to_string(i) +
                         " before the end of the file");
            values.push_back(parse(token, what));
            check(values.back(), lastLine_);
        }
        return values;
    }

private:
    // The next run of characters between whitespace and commas; empty at the end of the text.
    std::string_view nextToken() {
        while (pos_ < text_.size() && (isSpace(text_[pos_]) || text_[pos_] == ',')) {
            const char c = text_[pos_++];
            if (c == '\n' || (c == '\r' && (pos_ >= text_.size() || text_[pos_] != '\n'))) ++line_;
        }
        const size_t start = pos_;
        while (pos_ < text_.size() && !isSpace(text_[pos_]) && text_[pos_] != ',') ++pos_;
        if (pos_ > start) lastLine_ = line_;
        return text_.substr(start, pos_ - start);
    }

    double parse(std::string_view token, const std::string& what) const {
        std::string_view digits = token;
        if (digits.size() > 1 && digits[0] == '+') digits.remove_prefix(1);  // from_chars rejects '+'
        double value = 0;
        const char* end = digits.data() + digits.size();
        const auto result = std::from_chars(digits.data(), end, value);
        if (result.ptr != end || (result.ec != std::errc() && result.ec != std::errc::result_out_of_range))
            fail(file_, lastLine_, "expected " + what + " (a number), found " + quoted(token));
        // Beyond a float (or a double: from_chars then reports out of range) is refused too.
        if (result.ec != std::errc() || !std::isfinite(float(value)))
            fail(file_, lastLine_, "expected " + what + ", a finite number, found " + quoted(token));
        return value;
    }

    std::string_view text_, file_;
    size_t pos_ = 0;
    int line_ = 1;
    int lastLine_ = 1;  // the line of the last token read, or where the text ends
};

// Angle `phi` (degrees) taken into [first, first + 360) for a table whose horizontal angles start
// at `first` (0 or 90). The unfolded table's mirrored angles are made by this same function, so
// that an angle computed as the test of a symmetry computes it lands on the table's angle exactly.
double reduceHorizontal(double phi, double first) {
    phi = std::fmod(phi, 360.0);
    if (phi < 0) phi += 360.0;
    if (phi < first) phi += 360.0;
    return phi;
}

// The file's horizontal angles unfolded over a whole turn, each with the index of the file's
// column it takes its values from; the last is the first plus 360 (LM-63-2002, 5.15: the last
// horizontal angle gives the symmetry).
std::vector<std::pair<double, int>> unfoldHorizontal(const std::vector<double>& h) {
    const int n = int(h.size());
    std::vector<std::pair<double, int>> nodes;
    const double first = h.front(), last = h.back();
    if (n == 1) {  // 0 only: the same values at every horizontal angle
        nodes = {{0.0, 0}, {360.0, 0}};
    } else if (first == 90.0) {  // 90..270: mirrored about the 90-270 plane, phi -> 180 - phi
        for (int j = 0; j < n; ++j) nodes.push_back({h[j], j});
        for (int j = n - 2; j >= 1; --j) nodes.push_back({reduceHorizontal(180.0 - h[j], 90.0), j});
        nodes.push_back({450.0, 0});
    } else if (last == 90.0) {  // each quadrant mirrors the first
        for (int j = 0; j < n; ++j) nodes.push_back({h[j], j});
        for (int j = n - 2; j >= 0; --j) nodes.push_back({180.0 - h[j], j});
        for (int j = 1; j < n; ++j) nodes.push_back({180.0 + h[j], j});
        for (int j = n - 2; j >= 0; --j) nodes.push_back({360.0 - h[j], j});
    } else if (last == 180.0) {  // mirrored about the 0-180 plane, phi -> 360 - phi
        for (int j = 0; j < n; ++j) nodes.push_back({h[j], j});
        for (int j = n - 2; j >= 0; --j) nodes.push_back({360.0 - h[j], j});
    } else {  // a whole turn; from the last angle on to 360 towards the values at 0
        for (int j = 0; j < n; ++j) nodes.push_back({h[j], j});
        if (last < 360.0) nodes.push_back({360.0, 0});
    }
    return nodes;
}

// The cell index i with a[i] <= x <= a[i + 1] and the fraction of the way from a[i] to a[i + 1];
// `a` has at least two entries and x is within [a.front(), a.back()].
std::pair<size_t, double> locate(const std::vector<double>& a, double x) {
    size_t i = size_t(std::upper_bound(a.begin(), a.end(), x) - a.begin());
    i = std::clamp<size_t>(i, 1, a.size() - 1) - 1;
    const double width = a[i + 1] - a[i];
    // Two mirrored angles may round to one: a cell of no width takes its first angle's values.
    const double t = width > 0 ? std::clamp((x - a[i]) / width, 0.0, 1.0) : 0.0;
    return {i, t};
}

}  // namespace

float IesProfile::candelaAt(double verticalDegrees, double horizontalDegrees) const {
    if (vertical_.size() < 2 || !std::isfinite(verticalDegrees) || !std::isfinite(horizontalDegrees))
        return 0;
    if (verticalDegrees < vertical_.front() || verticalDegrees > vertical_.back()) return 0;
    const auto [i, t] = locate(vertical_, verticalDegrees);
    const auto [j, u] = locate(horizontal_, reduceHorizontal(horizontalDegrees, horizontal_.front()));
    const size_t nv = vertical_.size();
    // (1 - t) a + t b rather than a + t (b - a): exactly a at t = 0 and exactly b at t = 1.
    const auto lerp = [](double a, double b, double s) { return (1.0 - s) * a + s * b; };
    const double at0 = lerp(candela_[j * nv + i], candela_[j * nv + i + 1], t);
    const double at1 = lerp(candela_[(j + 1) * nv + i], candela_[(j + 1) * nv + i + 1], t);
    return float(lerp(at0, at1, u));
}

float IesProfile::intensity(Vec3f d) const {
    const double x = d.x, y = d.y, z = d.z;
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || (x == 0 && y == 0 && z == 0)) return 0;
    const double theta = std::atan2(std::hypot(x, y), z) / kRadiansPerDegree;
    const double phi = std::atan2(y, x) / kRadiansPerDegree;
    return candelaAt(theta, phi);
}

IesProfile readIesProfile(const std::filesystem::path& path) {
    const std::string text = InputFile(path, "IES file", limits::kMaxIesFileBytes).readAll();
    return readIesProfileText(text, path.string());
}

IesProfile readIesProfileText(std::string_view text, std::string_view file) {
    if (text.size() > limits::kMaxIesFileBytes)
        fail(file, 0,
             "the IES file is " + describeBytes(text.size()) + "; penumbra reads at most " +
                 describeBytes(limits::kMaxIesFileBytes));
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte order mark
    Reader in(text, file);
    IesProfile profile;

    // The identifier line, then keyword lines (LM-63-1986: any text) up to the TILT line.
    std::string_view tilt;
    bool foundTilt = false, firstLine = true;
    int tiltLine = 0;
    while (!in.atEnd() && !foundTilt) {
        tiltLine = in.line();
        const std::string_view line = trim(in.readLine());
        if (firstLine) {
            firstLine = false;
            if (line == "IESNA91")
                profile.version_ = IesVersion::Lm63_1991;
            else if (line == "IESNA:LM-63-1995")
                profile.version_ = IesVersion::Lm63_1995;
            else if (line == "IESNA:LM-63-2002")
                profile.version_ = IesVersion::Lm63_2002;
            else if (line == "IES:LM-63-2019")
                profile.version_ = IesVersion::Lm63_2019;
            else
                profile.version_ = IesVersion::Lm63_1986;  // no identifier: this line is text, or TILT
            if (profile.version_ != IesVersion::Lm63_1986) continue;
        }
        if (line.size() >= 4 && equalsIgnoringCase(line.substr(0, 4), "TILT")) {
            const std::string_view rest = trim(line.substr(4));
            if (!rest.empty() && rest[0] == '=') {
                tilt = trim(rest.substr(1));
                foundTilt = true;
            }
        }
    }
    if (!foundTilt)
        fail(file, std::max(1, in.line() - (text.empty() || isSpace(text.back()) ? 1 : 0)),
             "expected a line TILT=NONE, TILT=INCLUDE or TILT=<file> before the end of the file (IES LM-63)");

    if (equalsIgnoringCase(tilt, "INCLUDE")) {
        // The tilt table gives the lamp's output at other tilts than it was measured at; the
        // profile is of the luminaire as measured, so the table is read and not applied.
        in.integer("the lamp-to-luminaire geometry of TILT=INCLUDE", 1, 3);
        const int n = in.integer("the number of tilt angles", 0, limits::kMaxIesAngles);
        in.list(n, "tilt angles", [](double, int) {});
        in.list(n, "tilt multiplying factors", [](double, int) {});
    } else if (!equalsIgnoringCase(tilt, "NONE")) {
        fail(file, tiltLine,
             "TILT=" + quoted(tilt) +
                 " names a file of tilt data; only TILT=NONE and TILT=INCLUDE are supported");
    }

    // The photometric line.
    profile.lampCount_ = in.integer("the number of lamps", 1, 1 << 20);
    profile.lumensPerLamp_ = in.number("the lumens per lamp (-1 for absolute photometry)");
    const double candelaMultiplier = in.number("the candela multiplier");
    if (candelaMultiplier < 0)
        fail(file, in.line(), "expected a candela multiplier of 0 or more, found " + num(candelaMultiplier));
    const int nv = in.integer("the number of vertical angles", 2, limits::kMaxIesAngles);
    const int nh = in.integer("the number of horizontal angles", 1, limits::kMaxIesAngles);
    const int type = in.integer("the photometric type (1 = C, 2 = B, 3 = A)", 1, 3);
    if (type != 1)
        fail(file, in.line(),
             std::string("only type C photometry (photometric type 1) is supported; the file's is type ") +
                 (type == 2 ? "B (2)" : "A (3)"));
    in.integer("the units type (1 = feet, 2 = metres)", 1, 2);
    in.number("the width of the luminous opening");
    in.number("the length of the luminous opening");
    in.number("the height of the luminous opening");

    // The ballast line. The second factor is the ballast-lamp photometric factor up to LM-63-1995;
    // LM-63-2002 made it "future use" (to be 1), so it is ignored there.
    const bool useBallastLampFactor = profile.version_ == IesVersion::Lm63_1986 ||
                                      profile.version_ == IesVersion::Lm63_1991 ||
                                      profile.version_ == IesVersion::Lm63_1995;
    const double ballastFactor = in.number("the ballast factor");
    if (ballastFactor < 0)
        fail(file, in.line(), "expected a ballast factor of 0 or more, found " + num(ballastFactor));
    const double ballastLampFactor = in.number("the ballast-lamp photometric factor");
    if (useBallastLampFactor && ballastLampFactor < 0)
        fail(file, in.line(),
             "expected a ballast-lamp photometric factor of 0 or more, found " + num(ballastLampFactor));
    in.number("the input watts");
    const double multiplier =
        candelaMultiplier * ballastFactor * (useBallastLampFactor ? ballastLampFactor : 1.0);

    // The angles (LM-63-2002, 5.14 and 5.15).
    double previous = -1;
    std::vector<double> vertical = in.list(nv, "vertical angles", [&](double v, int line) {
        if (previous < 0 && v != 0 && v != 90)
            fail(file, line, "expected the first vertical angle to be 0 or 90 (type C), found " + num(v));
        if (previous >= 0 && !(v > previous))
            fail(file, line,
                 "expected the vertical angles to increase, found " + num(v) + " after " + num(previous));
        if (v > 180) fail(file, line, "expected vertical angles of at most 180, found " + num(v));
        previous = v;
    });
    previous = -1;
    double firstHorizontal = 0;
    int lastHorizontalLine = 0;
    std::vector<double> horizontal = in.list(nh, "horizontal angles", [&](double h, int line) {
        if (previous < 0 && h != 0 && !(h == 90 && nh > 1))
            fail(file, line,
                 "expected the first horizontal angle to be 0 (or 90 for 90..270), found " + num(h));
        if (previous < 0) firstHorizontal = h;
        if (previous >= 0 && !(h > previous))
            fail(file, line,
                 "expected the horizontal angles to increase, found " + num(h) + " after " + num(previous));
        previous = h;
        lastHorizontalLine = line;
    });
    {
        const double last = horizontal.back();
        const bool valid = firstHorizontal == 90
                               ? last == 270
                               : (last == 0 || last == 90 || last == 180 || (last > 180 && last <= 360));
        if (!valid)
            fail(file, lastHorizontalLine,
                 firstHorizontal == 90
                     ? "expected horizontal angles from 90 to end at 270, found " + num(last)
                     : "expected the last horizontal angle to be 0, 90, 180, or more than 180 and at most "
                       "360, found " +
                           num(last));
    }

    // The candela values, horizontal angle by horizontal angle.
    const std::vector<double> values = in.list(
        nv * nh,
        "candela values (" + std::to_string(nv) + " vertical x " + std::to_string(nh) + " horizontal)",
        [&](double c, int line) {
            if (c < 0) fail(file, line, "expected candela values of 0 or more, found " + num(c));
            if (!std::isfinite(float(c * multiplier)))
                fail(file, line,
                     "the candela value " + num(c) + " times the multipliers is beyond the range of a float");
        });

    // Unfold the symmetries.
    const std::vector<std::pair<double, int>> nodes = unfoldHorizontal(horizontal);
    profile.vertical_ = std::move(vertical);
    profile.horizontal_.reserve(nodes.size());
    profile.candela_.reserve(nodes.size() * size_t(nv));
    for (const auto& [angle, column] : nodes) {
        profile.horizontal_.push_back(angle);
        for (int i = 0; i < nv; ++i)
            profile.candela_.push_back(float(values[size_t(column) * size_t(nv) + size_t(i)] * multiplier));
    }
    profile.maxCandela_ = *std::max_element(profile.candela_.begin(), profile.candela_.end());

    // The flux of the bilinear interpolant. Over a cell [t0, t1] x [p0, p1] (radians) with
    // s = (theta - t0) / (t1 - t0), the integral over phi of the bilinear interpolant is
    // (p1 - p0) times the mean of its values at p0 and p1, linear in s: a (1 - s) + b s, with a and b
    // the means of the cell's corners at t0 and at t1. Then
    //   int_t0^t1 s sin(theta) dtheta       = -cos t1 + (sin t1 - sin t0) / (t1 - t0),
    //   int_t0^t1 (1 - s) sin(theta) dtheta =  cos t0 - (sin t1 - sin t0) / (t1 - t0).
    double flux = 0;
    const auto& v = profile.vertical_;
    const auto& h = profile.horizontal_;
    for (size_t i = 0; i + 1 < v.size(); ++i) {
        const double t0 = v[i] * kRadiansPerDegree, t1 = v[i + 1] * kRadiansPerDegree;
        if (!(t1 > t0)) continue;  // two angles a rounding apart
        const double chord = (std::sin(t1) - std::sin(t0)) / (t1 - t0);
        const double w0 = std::max(0.0, std::cos(t0) - chord), w1 = std::max(0.0, chord - std::cos(t1));
        for (size_t j = 0; j + 1 < h.size(); ++j) {
            const double dphi = (h[j + 1] - h[j]) * kRadiansPerDegree;
            const double a = 0.5 * (double(profile.value(i, j)) + double(profile.value(i, j + 1)));
            const double b = 0.5 * (double(profile.value(i + 1, j)) + double(profile.value(i + 1, j + 1)));
            flux += dphi * (w0 * a + w1 * b);
        }
    }
    profile.totalFlux_ = flux;
    return profile;
}

}  // namespace penumbra
