// The IES LM-63 reader and the profile it yields: the file's values come back exactly at its
// angles, in every region a symmetry unfolds them to, times the multipliers; between angles the
// intensity is bilinear; the flux is the closed form for isotropic and cosine distributions and
// agrees with a brute-force quadrature; directions outside the vertical range emit nothing; and
// malformed files are refused naming the line and what was expected. Expected values are the
// fixtures' own numbers (tests/data/ies/), written out here.
#include "lights/ies_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"

namespace penumbra {
namespace {

constexpr double kPi = 3.14159265358979323846;

IesProfile fixture(const std::string& name) {
    return readIesProfile(std::string(PENUMBRA_TEST_DATA_DIR) + "/ies/" + name);
}

// The fixture's table: vertical and horizontal angles as the file lists them, and the expected
// candela (file value times the multipliers) at [horizontal][vertical].
struct Table {
    std::vector<double> vertical, horizontal;
    std::vector<std::vector<double>> candela;
};

// Every angle a symmetry maps horizontal angle h to (degrees, as a caller would compute them).
std::vector<double> images(double h, double first, double last) {
    if (first == 90) return {h, 180.0 - h};  // about the 90-270 plane
    if (last == 0) return {h, 45.0, 123.0, 270.0, 359.0};
    if (last == 90) return {h, 180.0 - h, 180.0 + h, 360.0 - h};
    if (last == 180) return {h, 360.0 - h};
    return {h, h - 360.0, h + 720.0};
}

void expectTableExactly(const IesProfile& profile, const Table& table) {
    for (size_t j = 0; j < table.horizontal.size(); ++j)
        for (size_t i = 0; i < table.vertical.size(); ++i)
            for (double h : images(table.horizontal[j], table.horizontal.front(), table.horizontal.back()))
                EXPECT_EQ(profile.candelaAt(table.vertical[i], h), float(table.candela[j][i]))
                    << "vertical " << table.vertical[i] << ", horizontal " << h;
}

// Quadrant symmetry, LM-63-2002: multiplier 2 x ballast factor 0.75; the "future use" 0.5 ignored.
const Table kQuadrant{{0, 45, 90}, {0, 30, 90}, {{150, 120, 30}, {180, 135, 45}, {240, 150, 60}}};
// Bilateral symmetry, LM-63-1995, upper hemisphere: 0.5 x 1 x ballast-lamp photometric factor 0.25.
const Table kBilateral{{90, 120, 180}, {0, 45, 135, 180}, {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}}};
// Bilateral about the 90-270 plane, LM-63-2002, multiplier 10.
const Table kBilateral90{{0, 60, 120, 180},
                         {90, 150, 200, 270},
                         {{10, 20, 30, 40}, {50, 60, 70, 80}, {90, 100, 110, 120}, {130, 140, 150, 160}}};
// No symmetry, horizontal 0..300, TILT=INCLUDE.
const Table kFull{{0, 30, 90, 180},
                  {0, 60, 150, 240, 300},
                  {{10, 20, 30, 40}, {11, 21, 31, 41}, {12, 22, 32, 42}, {13, 23, 33, 43}, {14, 24, 34, 44}}};

TEST(IesProfile, QuadrantSymmetryGivesTheTableInEveryQuadrant) {
    const IesProfile p = fixture("quadrant_2002.ies");
    EXPECT_EQ(p.version(), IesVersion::Lm63_2002);
    EXPECT_TRUE(p.absolutePhotometry());
    expectTableExactly(p, kQuadrant);
    EXPECT_EQ(p.maxCandela(), 240.0f);
}

TEST(IesProfile, BilateralSymmetryGivesTheTableOnBothSides) {
    const IesProfile p = fixture("bilateral_1995.ies");
    EXPECT_EQ(p.version(), IesVersion::Lm63_1995);
    EXPECT_FALSE(p.absolutePhotometry());
    EXPECT_EQ(p.lumensPerLamp(), 1000.0);
    expectTableExactly(p, kBilateral);
    EXPECT_EQ(p.maxCandela(), 12.0f);
}

TEST(IesProfile, BilateralSymmetryAbout90To270GivesTheTableOnBothSides) {
    const IesProfile p = fixture("bilateral_90_270_2002.ies");
    expectTableExactly(p, kBilateral90);
    // 0 and 360 mirror 180, which is not a table angle: midway between 150 and 200 in the file.
    for (size_t i = 0; i < kBilateral90.vertical.size(); ++i) {
        const double at180 = kBilateral90.candela[1][i] +
                             (30.0 / 50.0) * (kBilateral90.candela[2][i] - kBilateral90.candela[1][i]);
        EXPECT_NEAR(p.candelaAt(kBilateral90.vertical[i], 0.0), at180, 1e-4);
        EXPECT_NEAR(p.candelaAt(kBilateral90.vertical[i], 180.0), at180, 1e-4);
    }
}

TEST(IesProfile, NoSymmetryWrapsFromTheLastHorizontalAngleToZero) {
    const IesProfile p = fixture("full_2002.ies");
    expectTableExactly(p, kFull);
    // Between 300 and 360 towards the values at 0: at 330, midway.
    for (size_t i = 0; i < kFull.vertical.size(); ++i)
        EXPECT_FLOAT_EQ(p.candelaAt(kFull.vertical[i], 330.0),
                        0.5f * float(kFull.candela[4][i] + kFull.candela[0][i]));
}

TEST(IesProfile, RotationalSymmetryIsTheSameAtEveryHorizontalAngle) {
    const IesProfile p = fixture("lm63_1991.ies");  // TILT=INCLUDE, values 30 20 10
    EXPECT_EQ(p.version(), IesVersion::Lm63_1991);
    expectTableExactly(p, Table{{0, 90, 180}, {0}, {{30, 20, 10}}});
}

TEST(IesProfile, Lm63_1986LayoutAppliesTheBallastLampFactor) {
    const IesProfile p = fixture("lm63_1986.ies");
    EXPECT_EQ(p.version(), IesVersion::Lm63_1986);
    expectTableExactly(p, Table{{0, 90}, {0}, {{100, 50}}});
}

TEST(IesProfile, MidwayBetweenAnglesIsTheMean) {
    const IesProfile p = fixture("full_2002.ies");
    const Table& t = kFull;
    for (size_t j = 0; j + 1 < t.horizontal.size(); ++j)
        for (size_t i = 0; i + 1 < t.vertical.size(); ++i) {
            const double vm = 0.5 * (t.vertical[i] + t.vertical[i + 1]);
            const double hm = 0.5 * (t.horizontal[j] + t.horizontal[j + 1]);
            const double a = t.candela[j][i], b = t.candela[j][i + 1], c = t.candela[j + 1][i],
                         d = t.candela[j + 1][i + 1];
            EXPECT_FLOAT_EQ(p.candelaAt(vm, t.horizontal[j]), float(0.5 * (a + b)));
            EXPECT_FLOAT_EQ(p.candelaAt(t.vertical[i], hm), float(0.5 * (a + c)));
            EXPECT_FLOAT_EQ(p.candelaAt(vm, hm), float(0.25 * (a + b + c + d)));
            // A quarter of the way in vertical angle: linear in the angle, not in its cosine.
            const double vq = t.vertical[i] + 0.25 * (t.vertical[i + 1] - t.vertical[i]);
            EXPECT_FLOAT_EQ(p.candelaAt(vq, t.horizontal[j]), float(0.75 * a + 0.25 * b));
        }
}

TEST(IesProfile, DirectionsFollowTheDocumentedFrame) {
    const IesProfile p = fixture("full_2002.ies");
    // +z is the nadir (vertical 0), -z the zenith (180); +x horizontal 0, +y horizontal 90.
    EXPECT_FLOAT_EQ(p.intensity({0, 0, 1}), 10.0f);
    EXPECT_FLOAT_EQ(p.intensity({0, 0, -3}), 40.0f);
    EXPECT_FLOAT_EQ(p.intensity({2, 0, 0}), 30.0f);
    // +y: horizontal 90, a third of the way from 60 to 150 at vertical 90.
    EXPECT_NEAR(p.intensity({0, 1, 0}), 31.0f + (32.0f - 31.0f) / 3.0f, 1e-4f);
    // -x: horizontal 180, a third of the way from 150 to 240.
    EXPECT_NEAR(p.intensity({-1, 0, 0}), 32.0f + (33.0f - 32.0f) / 3.0f, 1e-4f);
    // Vertical 30 towards horizontal 60: (sin 30 cos 60, sin 30 sin 60, cos 30).
    const float s = 0.5f, c = std::sqrt(3.0f) / 2;
    EXPECT_NEAR(p.intensity({s * 0.5f, s * c, c}), 21.0f, 1e-3f);
    EXPECT_EQ(p.intensity({0, 0, 0}), 0.0f);
    EXPECT_EQ(p.intensity({NAN, 0, 1}), 0.0f);
}

TEST(IesProfile, OutsideTheVerticalRangeEmitsNothing) {
    const IesProfile lower = fixture("quadrant_2002.ies");  // vertical 0..90
    EXPECT_EQ(lower.candelaAt(90.0, 0.0), 30.0f);
    EXPECT_EQ(lower.candelaAt(90.001, 0.0), 0.0f);
    EXPECT_EQ(lower.candelaAt(180.0, 0.0), 0.0f);
    EXPECT_EQ(lower.candelaAt(-1.0, 0.0), 0.0f);
    EXPECT_EQ(lower.intensity({0, 0, -1}), 0.0f);
    EXPECT_GT(lower.intensity({0, 0, 1}), 0.0f);
    const IesProfile upper = fixture("bilateral_1995.ies");  // vertical 90..180
    EXPECT_EQ(upper.candelaAt(89.999, 0.0), 0.0f);
    EXPECT_EQ(upper.intensity({0, 0, 1}), 0.0f);
    EXPECT_EQ(upper.intensity({0, 0, -1}), 3.0f);
}

TEST(IesProfile, IsotropicFluxIs4PiTimesTheIntensity) {
    const IesProfile p = fixture("isotropic_2002.ies");
    // Exact for the interpolant (a constant here) up to double rounding over a few cells.
    EXPECT_NEAR(p.totalFlux(), 400.0 * kPi, 1e-9 * 400.0 * kPi);
}

TEST(IesProfile, CosineFluxIsPiTimesTheIntensityAtNadir) {
    // I = 1000 cos(theta) tabulated every h = 5 degrees, values rounded to 1e-6 cd. Linear
    // interpolation of a function with |f''| <= I0 errs by at most I0 h^2 / 8, and lies below the
    // concave cosine, so the interpolant's flux is within 2 pi (I0 h^2 / 8 + 5e-7) below pi I0.
    const IesProfile p = fixture("cosine_1995.ies");
    const double i0 = 1000, h = 5 * kPi / 180;
    const double exact = kPi * i0, rounding = 2 * kPi * 5e-7;
    EXPECT_LE(p.totalFlux(), exact + rounding);
    EXPECT_GE(p.totalFlux(), exact - 2 * kPi * (i0 * h * h / 8) - rounding);
    EXPECT_EQ(p.maxCandela(), 1000.0f);
}

// A midpoint rule over the sphere, of intensity() along each direction: the closed form must
// agree with it for every symmetry and vertical range.
TEST(IesProfile, FluxAgreesWithBruteForceQuadrature) {
    for (const char* name :
         {"full_2002.ies", "quadrant_2002.ies", "bilateral_1995.ies", "bilateral_90_270_2002.ies"}) {
        const IesProfile p = fixture(name);
        const int nt = 720, np = 1440;
        double sum = 0;
        for (int a = 0; a < nt; ++a) {
            const double theta = (a + 0.5) * kPi / nt;
            for (int b = 0; b < np; ++b) {
                const double phi = (b + 0.5) * 2 * kPi / np;
                const Vec3f d(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                              float(std::cos(theta)));
                sum += p.intensity(d) * std::sin(theta);
            }
        }
        const double quadrature = sum * (kPi / nt) * (2 * kPi / np);
        // The midpoint rule errs by O(h^2) relative on the interpolant's smooth pieces and at its
        // kinks, h = 0.25 degrees = 4.4e-3 radians (h^2 = 1.9e-5); the ends of the vertical
        // ranges (90) fall on its cells' edges, so the jumps there cost nothing. (It agrees to
        // 2.4e-6 or better for these files.)
        EXPECT_NEAR(p.totalFlux(), quadrature, 2e-5 * quadrature) << name;
        EXPECT_GT(p.totalFlux(), 0.0) << name;
    }
}

// ---------------------------------------------------------------------------------------------
// Malformed files: each refused with the file, the line and what was expected.

// A valid LM-63-2002 file, one line per entry; each test replaces one.
std::vector<std::string> baseLines() {
    return {
        "IESNA:LM-63-2002",      // 1
        "[TEST] base",           // 2
        "TILT=NONE",             // 3
        "1 -1 1 3 2 1 2 0 0 0",  // 4
        "1 1 0",                 // 5
        "0 45 90",               // 6
        "0 90",                  // 7
        "10 20 30",              // 8
        "40 50 60",              // 9
    };
}

std::string join(const std::vector<std::string>& lines, const char* end = "\n") {
    std::string text;
    for (const std::string& l : lines) text += l + end;
    return text;
}

void expectRefused(const std::string& text, int line, const std::string& what) {
    try {
        readIesProfileText(text, "x.ies");
        ADD_FAILURE() << "read: " << text;
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(e.where().line, line) << message;
        EXPECT_EQ(message.rfind("x.ies:" + std::to_string(line) + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(what), std::string::npos) << message << "\n  expected: " << what;
    }
}

std::string with(int line, const std::string& replacement) {
    std::vector<std::string> lines = baseLines();
    lines[size_t(line - 1)] = replacement;
    return join(lines);
}

TEST(IesProfileMalformed, TheBaseFileReads) {
    const IesProfile p = readIesProfileText(join(baseLines()), "x.ies");
    EXPECT_EQ(p.candelaAt(45, 270), 50.0f);
    // CRLF line endings, commas and numbers split across lines read the same.
    const IesProfile q = readIesProfileText(join(baseLines(), "\r\n"), "x.ies");
    EXPECT_EQ(q.candelaAt(45, 270), 50.0f);
    const IesProfile r = readIesProfileText(
        "IESNA:LM-63-2002\r\nTILT=NONE\r\n1,-1,1,3,2,1,2,0,0,0,1,1,0,0,\r\n45\r\n90 0 90 10 20 30 40 50 "
        "60\r\n",
        "x.ies");
    EXPECT_EQ(r.candelaAt(45, 270), 50.0f);
}

TEST(IesProfileMalformed, EmptyOrWithoutTilt) {
    expectRefused("", 1, "expected a line TILT=NONE");
    expectRefused("IESNA:LM-63-2002\n[TEST] x\n[MANUFAC] y\n", 3, "expected a line TILT=NONE");
}

TEST(IesProfileMalformed, TiltFile) {
    expectRefused(with(3, "TILT=lamp.tlt"), 3, "names a file of tilt data");
}

TEST(IesProfileMalformed, TiltIncludeCutShort) {
    expectRefused("IESNA:LM-63-2002\nTILT=INCLUDE\n1\n3\n0 45 90\n1 1\n", 6,
                  "expected 3 tilt multiplying factors, found 2 before the end of the file");
}

TEST(IesProfileMalformed, TypeAAndBPhotometry) {
    expectRefused(with(4, "1 -1 1 3 2 2 2 0 0 0"), 4, "only type C photometry");
    expectRefused(with(4, "1 -1 1 3 2 3 2 0 0 0"), 4, "only type C photometry");
    expectRefused(with(4, "1 -1 1 3 2 4 2 0 0 0"), 4, "the photometric type");
}

TEST(IesProfileMalformed, CountsOutOfRange) {
    expectRefused(with(4, "1 -1 1 5000 2 1 2 0 0 0"), 4,
                  "number of vertical angles (an integer from 2 to 4096)");
    expectRefused(with(4, "1 -1 1 3 0 1 2 0 0 0"), 4,
                  "number of horizontal angles (an integer from 1 to 4096)");
    expectRefused(with(4, "1 -1 1 3 2.5 1 2 0 0 0"), 4, "found '2.5'");
    expectRefused(with(4, "1 -1 1 3 2 1 7 0 0 0"), 4, "the units type");
    // The largest table in a small file: refused when the numbers run out, nothing allocated first.
    expectRefused("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 4096 4096 1 2 0 0 0\n1 1 0\n0 1 2 3\n", 5,
                  "expected 4096 vertical angles, found 4 before the end of the file");
}

TEST(IesProfileMalformed, NotANumber) {
    expectRefused(with(8, "10 abc 30"), 8,
                  "candela values (3 vertical x 2 horizontal) (a number), found 'abc'");
    expectRefused(with(5, "1 1 0x10"), 5, "the input watts (a number), found '0x10'");
}

TEST(IesProfileMalformed, NonFiniteNumbers) {
    expectRefused(with(9, "40 nan 60"), 9, "a finite number, found 'nan'");
    expectRefused(with(6, "0 inf 90"), 6, "a finite number, found 'inf'");
    expectRefused(with(8, "10 1e39 30"), 8, "a finite number, found '1e39'");
    // Finite alone, beyond a float once multiplied.
    expectRefused(with(4, "1 -1 1e38 3 2 1 2 0 0 0"), 8, "beyond the range of a float");
}

TEST(IesProfileMalformed, NegativeValues) {
    expectRefused(with(9, "40 -50 60"), 9, "expected candela values of 0 or more, found -50");
    expectRefused(with(4, "1 -1 -2 3 2 1 2 0 0 0"), 4, "candela multiplier of 0 or more");
    expectRefused(with(5, "-1 1 0"), 5, "ballast factor of 0 or more");
}

TEST(IesProfileMalformed, CutShort) {
    std::vector<std::string> lines = baseLines();
    lines.pop_back();
    expectRefused(
        join(lines), 8,
        "expected 6 candela values (3 vertical x 2 horizontal), found 3 before the end of the file");
    lines.resize(5);
    expectRefused(join(lines), 5, "expected 3 vertical angles, found 0 before the end of the file");
    lines.resize(4);
    expectRefused(join(lines), 4, "expected the ballast factor, found the end of the file");
}

TEST(IesProfileMalformed, VerticalAngles) {
    expectRefused(with(6, "10 45 90"), 6, "first vertical angle to be 0 or 90");
    expectRefused(with(6, "0 45 45"), 6, "vertical angles to increase, found 45 after 45");
    expectRefused(with(6, "0 90 45"), 6, "vertical angles to increase");
    expectRefused(with(6, "0 90 190"), 6, "vertical angles of at most 180");
}

TEST(IesProfileMalformed, HorizontalAngles) {
    expectRefused(with(7, "10 90"), 7, "first horizontal angle to be 0");
    expectRefused(with(7, "0 120"), 7, "last horizontal angle to be 0, 90, 180, or more than 180");
    expectRefused(with(7, "0 400"), 7, "last horizontal angle");
    expectRefused(with(7, "90 200"), 7, "horizontal angles from 90 to end at 270");
    expectRefused(with(7, "90 90"), 7, "horizontal angles to increase");
}

TEST(IesProfileMalformed, CrlfLineNumbers) {
    std::vector<std::string> lines = baseLines();
    lines[8] = "40 -50 60";
    expectRefused(join(lines, "\r\n"), 9, "expected candela values of 0 or more");
    expectRefused(join(lines, "\r"), 9, "expected candela values of 0 or more");
}

TEST(IesProfileMalformed, MissingFile) {
    try {
        readIesProfile(std::string(PENUMBRA_TEST_DATA_DIR) + "/ies/no_such_file.ies");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("no_such_file.ies"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace penumbra
