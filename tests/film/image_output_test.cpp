// Image output: the EXR's beauty is the film's mean radiance in float precision with the render metadata,
// the display image is the shipped (or $OCIO's) view transform quantized to 8 bits, and writes
// are atomic (no temporary file survives, failures are InputErrors naming the path).
#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "film/display_image.h"
#include "film/film_exr.h"
#include "film/image_plugin_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
namespace OCIO = OCIO_NAMESPACE;

const std::string kShippedConfig = std::string(PENUMBRA_SOURCE_DIR) + "/film/ocio/config.ocio";

// The sRGB encoding of IEC 61966-2-1, clamped to [0, 1] as the display image is.
double srgbEncode(double linear) {
    const double v = std::clamp(linear, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

struct Image {
    int width = 0, height = 0, channels = 0;
    OIIO::ImageSpec spec;
    std::vector<float> pixels;  // normalized to [0, 1] for 8-bit files
};

Image readImage(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
        return {};
    }
    Image image;
    image.spec = in->spec();
    image.width = image.spec.width;
    image.height = image.spec.height;
    image.channels = std::min(image.spec.nchannels, 3);  // R, G, B come first (the EXR has AOVs after them)
    image.pixels.resize(size_t(image.width) * image.height * image.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
        << in->geterror();
    in->close();
    return image;
}

// Names of the files in `dir`, to check that no temporary file was left behind.
std::vector<std::string> listFolder(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// A film whose pixel (i, 0) has the mean radiance values[i] (grey), reached through two weighted
// samples so that the output really divides sums by weights.
Film greyRamp(const std::vector<float>& values) {
    Film film(int(values.size()), 1);
    for (size_t i = 0; i < values.size(); ++i) {
        // (0.5 * 3v + 1.5 * v/3) / (0.5 + 1.5) = v.
        film.add(int(i), 0, Rgb(3.0f * values[i]), 0.5f);
        film.add(int(i), 0, Rgb(values[i] / 3.0f), 1.5f);
    }
    return film;
}

class ImageOutputTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               (std::string("penumbra-image-output-") + std::to_string(::getpid()) + "-" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        // Every test starts without $OCIO; the previous value is restored afterwards.
        if (const char* ocio = std::getenv("OCIO")) savedOcio_ = ocio;
        ::unsetenv("OCIO");
    }
    void TearDown() override {
        if (savedOcio_)
            ::setenv("OCIO", savedOcio_->c_str(), 1);
        else
            ::unsetenv("OCIO");
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    fs::path dir_;
    std::optional<std::string> savedOcio_;
};

TEST_F(ImageOutputTest, ExrRoundTripsMeansAndMetadata) {
    const int width = 5, height = 3;
    Film film(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            // Distinct channels over several orders of magnitude, plus zero-weight (black) pixel.
            if (x == 4 && y == 2) continue;
            const float base = std::pow(10.0f, float(x - 2)) * (1.0f + 0.37f * y);
            film.add(x, y, Rgb(base, 2.0f * base, 0.5f * base), 1.0f);
            film.add(x, y, Rgb(3.0f * base, 0.0f, base), 3.0f);
        }

    RenderMetadata meta;
    meta.samplesPerPixel = 256;
    meta.seed = 0xfedcba9876543210ull;  // needs all 64 bits
    meta.sampler = "stratified";
    meta.accelerator = "embree";
    meta.sceneFile = "scenes/cornell box.json";
    meta.renderSeconds = 12.375;
    meta.version = "0.1.0";

    // Missing parent folders are created.
    const fs::path path = dir_ / "nested" / "deeper" / "beauty.exr";
    writeExr(film, meta, path);
    ASSERT_TRUE(fs::is_regular_file(path));
    EXPECT_EQ(listFolder(path.parent_path()), std::vector<std::string>{"beauty.exr"});

    const Image image = readImage(path);
    ASSERT_EQ(image.width, width);
    ASSERT_EQ(image.height, height);
    ASSERT_EQ(image.channels, 3);
    EXPECT_EQ(image.spec.nchannels, 14);  // R, G, B, A, albedo, N, Z, variance (docs/exr-layout.md)
    EXPECT_EQ(image.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(std::vector<std::string>(image.spec.channelnames.begin(), image.spec.channelnames.begin() + 4),
              (std::vector<std::string>{"R", "G", "B", "A"}));

    const std::vector<float> expected = film.meanRgb();
    ASSERT_EQ(image.pixels.size(), expected.size());
    // Floats are stored as they are: the means come back exactly.
    for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(image.pixels[i], expected[i]) << "value " << i;
    // Spot-check one mean by hand: (1*b + 3*3b) / 4 = 2.5 b for red of pixel (2, 0) with b = 1.
    EXPECT_NEAR(image.pixels[3 * 2], 2.5f, 2.5f * 0x1p-20f);
    EXPECT_EQ(image.pixels[3 * (2 * width + 4)], 0.0f);

    const OIIO::ImageSpec& spec = image.spec;
    EXPECT_EQ(spec.get_int_attribute("penumbra:spp"), 256);
    EXPECT_EQ(spec.get_string_attribute("penumbra:seed"), "18364758544493064720");
    EXPECT_EQ(spec.get_string_attribute("penumbra:sampler"), "stratified");
    EXPECT_EQ(spec.get_string_attribute("penumbra:accel"), "embree");
    EXPECT_EQ(spec.get_string_attribute("penumbra:scene"), "scenes/cornell box.json");
    double seconds = 0.0;
    EXPECT_TRUE(spec.getattribute("penumbra:renderTime", OIIO::TypeDesc::DOUBLE, &seconds));
    EXPECT_EQ(seconds, 12.375);
    EXPECT_EQ(spec.get_string_attribute("penumbra:version"), "0.1.0");
    EXPECT_EQ(std::string(spec.get_string_attribute("Software")),
              std::string("penumbra ") + PENUMBRA_VERSION);
}

TEST_F(ImageOutputTest, ExrOverwritesAnExistingFile) {
    const fs::path path = dir_ / "out.exr";
    { std::ofstream(path) << "not an image"; }
    writeExr(greyRamp({0.25f, 4.0f}), RenderMetadata{}, path);
    const Image image = readImage(path);
    ASSERT_EQ(image.pixels.size(), 6u);
    EXPECT_EQ(image.pixels[0], 0.25f);
    EXPECT_EQ(image.pixels[3], 4.0f);
    EXPECT_EQ(listFolder(dir_), std::vector<std::string>{"out.exr"});
}

TEST_F(ImageOutputTest, PngIsTheSrgbEncodingOfTheMeans) {
    const std::vector<float> linear = {0.0f, 0.0031308f, 0.18f, 0.5f, 1.0f, 2.0f, 0.01f, -0.5f};
    const fs::path path = dir_ / "out.png";
    writeDisplayImage(greyRamp(linear), path);
    EXPECT_EQ(listFolder(dir_), std::vector<std::string>{"out.png"});

    const Image image = readImage(path);
    ASSERT_EQ(image.width, int(linear.size()));
    ASSERT_EQ(image.channels, 3);
    EXPECT_EQ(image.spec.format, OIIO::TypeDesc::UINT8);
    for (size_t i = 0; i < linear.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(image.pixels[3 * i + c], srgbEncode(linear[i]), 1.0 / 255.0)
                << "linear " << linear[i];
    // Exact ends: black stays 0 and anything at or above 1 is full white.
    EXPECT_EQ(image.pixels[0], 0.0f);
    EXPECT_EQ(image.pixels[3 * 4], 1.0f);
    EXPECT_EQ(image.pixels[3 * 5], 1.0f);
    EXPECT_EQ(image.pixels[3 * 7], 0.0f);
}

TEST_F(ImageOutputTest, JpegIsWrittenThroughTheSameTransform) {
    Film film(16, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) film.add(x, y, Rgb(0.18f), 1.0f);
    const fs::path path = dir_ / "out.jpg";
    writeDisplayImage(film, path);
    const Image image = readImage(path);
    ASSERT_EQ(image.width, 16);
    // A flat image survives JPEG almost exactly; allow two codes for the codec's rounding.
    for (float v : image.pixels) EXPECT_NEAR(v, srgbEncode(0.18), 2.0 / 255.0);
}

TEST_F(ImageOutputTest, NamedViewIsUsed) {
    const std::vector<float> linear = {0.0f, 0.18f, 0.5f, 1.5f};
    const fs::path path = dir_ / "raw.png";
    writeDisplayImage(greyRamp(linear), path, {"sRGB", "Raw"});
    const Image image = readImage(path);
    ASSERT_EQ(image.width, int(linear.size()));
    for (size_t i = 0; i < linear.size(); ++i)
        EXPECT_NEAR(image.pixels[3 * i], std::min(linear[i], 1.0f), 0.5 / 255.0 + 1e-6);
}

// The Filmic view against its stated curve (film/ocio/make_luts.py): a grey value v goes to
// x = (log2 v + 12.47393) / 16.5 and then through Wrensch's polynomial fit of AgX's sigmoid; greys
// are unchanged by the view's desaturation matrix. Exposure multiplies by 2^stops first.
TEST_F(ImageOutputTest, FilmicViewFollowsItsCurve) {
    auto curve = [](double v) {
        const double x = std::clamp((std::log2(v) + 12.47393) / 16.5, 0.0, 1.0);
        const double y = 15.5 * std::pow(x, 6) - 40.14 * std::pow(x, 5) + 31.96 * std::pow(x, 4) -
                         6.868 * std::pow(x, 3) + 0.4298 * x * x + 0.1191 * x - 0.00232;
        return std::clamp(y, 0.0, 1.0);
    };
    const std::vector<float> linear = {0.01f, 0.18f, 1.0f, 4.0f, 100.0f};
    writeDisplayImage(greyRamp(linear), dir_ / "filmic.png", {"sRGB", "Filmic"});
    writeDisplayImage(greyRamp(linear), dir_ / "filmic-up.png", {"sRGB", "Filmic", 2.0f});
    const Image image = readImage(dir_ / "filmic.png"), up = readImage(dir_ / "filmic-up.png");
    ASSERT_EQ(image.width, int(linear.size()));
    for (size_t i = 0; i < linear.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            // The LUT's 4096 entries and 8 bits: within a code and a half.
            EXPECT_NEAR(image.pixels[3 * i + c], curve(linear[i]), 1.5 / 255.0) << linear[i];
            EXPECT_NEAR(up.pixels[3 * i + c], curve(4.0 * linear[i]), 1.5 / 255.0) << linear[i];
        }
    // Highlights roll off instead of clipping: 4 is still below white, 100 at it.
    EXPECT_LT(image.pixels[3 * 3], 0.95f);
    EXPECT_GT(image.pixels[3 * 4], 0.99f);
    // The view is recorded in the image.
    EXPECT_EQ(image.spec.get_string_attribute("penumbra:view"), "Filmic");
    EXPECT_EQ(up.spec.get_string_attribute("penumbra:exposure"), "+2");
    EXPECT_NE(up.spec.get_string_attribute("ImageDescription").find("Filmic"), std::string::npos);
}

// The False Color view: luminance in bands of stops around 0.18 (film/ocio/make_luts.py).
TEST_F(ImageOutputTest, FalseColorViewShowsStopsAroundMiddleGrey) {
    // Middle grey, 3 stops over, 10 over, 10 under, 1 over.
    const std::vector<float> linear = {0.18f, 0.18f * 8.0f, 0.18f * 1024.0f, 0.18f / 1024.0f, 0.18f * 2.0f};
    writeDisplayImage(greyRamp(linear), dir_ / "false.png", {"sRGB", "False Color"});
    const Image image = readImage(dir_ / "false.png");
    ASSERT_EQ(image.width, int(linear.size()));
    auto expectColour = [&](int i, float r, float g, float b) {
        EXPECT_NEAR(image.pixels[3 * i + 0], r, 1.0 / 255.0) << i;
        EXPECT_NEAR(image.pixels[3 * i + 1], g, 1.0 / 255.0) << i;
        EXPECT_NEAR(image.pixels[3 * i + 2], b, 1.0 / 255.0) << i;
    };
    expectColour(0, 0.5f, 0.5f, 0.5f);    // middle grey
    expectColour(1, 0.95f, 0.85f, 0.0f);  // 3 stops over: yellow (2 to 4)
    expectColour(2, 1.0f, 0.0f, 0.0f);    // 10 stops over: red
    expectColour(3, 0.0f, 0.0f, 0.0f);    // 10 stops under: black
    expectColour(4, 0.25f, 0.75f, 0.2f);  // 1 stop over: green (0.5 to 2)
    EXPECT_EQ(image.spec.get_string_attribute("penumbra:view"), "False Color");
}

TEST_F(ImageOutputTest, UnknownDisplayOrViewListsTheAvailableOnes) {
    const Film film = greyRamp({0.5f});
    try {
        writeDisplayImage(film, dir_ / "a.png", {"P3", ""});
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("P3"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("sRGB"), std::string::npos) << e.what();
    }
    try {
        writeDisplayImage(film, dir_ / "a.png", {"sRGB", "Log"});
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("Log"), std::string::npos) << what;
        EXPECT_NE(what.find("Standard"), std::string::npos) << what;
        EXPECT_NE(what.find("Raw"), std::string::npos) << what;
    }
    EXPECT_TRUE(listFolder(dir_).empty());
}

TEST_F(ImageOutputTest, UnsupportedDisplayExtensionThrows) {
    EXPECT_THROW(writeDisplayImage(greyRamp({0.5f}), dir_ / "a.exr"), InputError);
    EXPECT_TRUE(listFolder(dir_).empty());
}

// An alternative config whose default display's default view is the identity and whose second
// view halves the values: the output must follow it when $OCIO names it.
constexpr const char* kAlternativeConfig = R"(ocio_profile_version: 2
roles:
  reference: lin
  scene_linear: lin
  default: lin
displays:
  Flat:
    - !<View> {name: Identity, colorspace: lin}
    - !<View> {name: Half, colorspace: half}
colorspaces:
  - !<ColorSpace>
    name: lin
  - !<ColorSpace>
    name: half
    from_scene_reference: !<MatrixTransform> {matrix: [0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1]}
)";

TEST_F(ImageOutputTest, OcioEnvironmentVariableSelectsTheConfig) {
    const fs::path configPath = dir_ / "alternative.ocio";
    { std::ofstream(configPath) << kAlternativeConfig; }
    const std::vector<float> linear = {0.0f, 0.18f, 0.5f, 0.8f};
    const Film film = greyRamp(linear);

    ::setenv("OCIO", configPath.c_str(), 1);
    writeDisplayImage(film, dir_ / "identity.png");
    writeDisplayImage(film, dir_ / "half.png", {"Flat", "Half"});
    // The shipped config's display is unknown to the alternative one.
    EXPECT_THROW(writeDisplayImage(film, dir_ / "srgb.png", {"sRGB", "Standard"}), InputError);
    ::unsetenv("OCIO");
    writeDisplayImage(film, dir_ / "shipped.png");
    // An empty $OCIO counts as unset.
    ::setenv("OCIO", "", 1);
    writeDisplayImage(film, dir_ / "empty-env.png");
    ::unsetenv("OCIO");

    const Image identity = readImage(dir_ / "identity.png");
    const Image half = readImage(dir_ / "half.png");
    const Image shipped = readImage(dir_ / "shipped.png");
    const Image emptyEnv = readImage(dir_ / "empty-env.png");
    ASSERT_EQ(identity.width, int(linear.size()));
    ASSERT_EQ(half.width, int(linear.size()));
    ASSERT_EQ(shipped.width, int(linear.size()));
    for (size_t i = 0; i < linear.size(); ++i) {
        const double tol = 0.5 / 255.0 + 1e-6;  // rounding to the nearest code
        EXPECT_NEAR(identity.pixels[3 * i], linear[i], tol);
        EXPECT_NEAR(half.pixels[3 * i], 0.5 * linear[i], tol);
        EXPECT_NEAR(shipped.pixels[3 * i], srgbEncode(linear[i]), 1.0 / 255.0);
        EXPECT_EQ(emptyEnv.pixels[3 * i], shipped.pixels[3 * i]);
    }
    // The two configs really disagree on mid-grey, so the comparison above means something.
    EXPECT_GT(std::abs(identity.pixels[3] - shipped.pixels[3]), 0.2f);
}

TEST_F(ImageOutputTest, BrokenOcioConfigThrowsInputError) {
    ::setenv("OCIO", (dir_ / "missing.ocio").c_str(), 1);
    EXPECT_THROW(writeDisplayImage(greyRamp({0.5f}), dir_ / "a.png"), InputError);
}

TEST_F(ImageOutputTest, UnwritablePathThrowsAndLeavesNoTemporaryFile) {
    const fs::path blocker = dir_ / "blocker";
    { std::ofstream(blocker) << "a regular file"; }
    const Film film = greyRamp({0.5f, 1.0f});

    // A path under a regular file: the folder cannot be created.
    for (const fs::path& path : {blocker / "out.exr", blocker / "sub" / "out.png"}) {
        try {
            if (path.extension() == ".exr")
                writeExr(film, RenderMetadata{}, path);
            else
                writeDisplayImage(film, path);
            FAIL() << "expected InputError for " << path;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(listFolder(dir_), std::vector<std::string>{"blocker"});

    // A destination that is a folder: the temporary file is written, the rename fails, and the
    // temporary file must be cleaned up.
    const fs::path folderTarget = dir_ / "target.exr";
    fs::create_directories(folderTarget / "keep");
    try {
        writeExr(film, RenderMetadata{}, folderTarget);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(folderTarget.string()), std::string::npos) << e.what();
    }
    EXPECT_EQ(listFolder(dir_), (std::vector<std::string>{"blocker", "target.exr"}));
    EXPECT_EQ(listFolder(folderTarget), std::vector<std::string>{"keep"});
}

// The EXR needs no OpenImageIO; the display image loads the plugin that holds it. (Each test
// runs in a process of its own, so nothing has loaded the plugin before.)
TEST_F(ImageOutputTest, OnlyTheDisplayImageLoadsTheImagePlugin) {
    const Film film = greyRamp({0.5f, 1.0f});
    writeExr(film, RenderMetadata{}, dir_ / "film.exr");
    readFilmExr(dir_ / "film.exr");
    EXPECT_FALSE(imagePluginLoaded());
    writeDisplayImage(film, dir_ / "film.png");
    EXPECT_TRUE(imagePluginLoaded());
    EXPECT_TRUE(fs::is_regular_file(imagePluginPath())) << imagePluginPath();
}

TEST(ShippedOcioConfig, ValidatesAndEncodesSrgb) {
    OCIO::ConstConfigRcPtr config;
    ASSERT_NO_THROW(config = OCIO::Config::CreateFromFile(kShippedConfig.c_str()));
    EXPECT_NO_THROW(config->validate());
    EXPECT_EQ(config->getMajorVersion(), 2u);

    EXPECT_STREQ(config->getDefaultDisplay(), "sRGB");
    EXPECT_STREQ(config->getDefaultView("sRGB"), "Standard");
    ASSERT_EQ(config->getNumViews("sRGB"), 4);
    EXPECT_STREQ(config->getView("sRGB", 1), "Filmic");
    EXPECT_STREQ(config->getView("sRGB", 2), "False Color");
    EXPECT_STREQ(config->getView("sRGB", 3), "Raw");

    for (const char* role : {OCIO::ROLE_SCENE_LINEAR, OCIO::ROLE_DEFAULT, OCIO::ROLE_REFERENCE}) {
        auto cs = config->getColorSpace(role);
        ASSERT_TRUE(cs) << role;
        EXPECT_STREQ(cs->getName(), "Linear Rec.709 (sRGB)") << role;
    }
    auto raw = config->getColorSpace(OCIO::ROLE_DATA);
    ASSERT_TRUE(raw);
    EXPECT_STREQ(raw->getName(), "Raw");
    EXPECT_TRUE(raw->isData());

    // The Standard view is the sRGB encoding (not its inverse): check it against the closed form
    // in floating point, across both segments of the curve.
    auto cpu = config->getProcessor(OCIO::ROLE_SCENE_LINEAR, "sRGB", "Standard", OCIO::TRANSFORM_DIR_FORWARD)
                   ->getDefaultCPUProcessor();
    for (float v : {0.0f, 0.001f, 0.0031308f, 0.01f, 0.18f, 0.5f, 0.9f, 1.0f}) {
        float rgb[3] = {v, v, v};
        cpu->applyRGB(rgb);
        // OCIO derives the break point from gamma and offset (0.0030399 vs the standard's
        // 0.0031308); the curves differ by under 1e-4 there, far below one 8-bit code.
        EXPECT_NEAR(rgb[0], srgbEncode(v), 2e-4) << v;
    }
}

}  // namespace
}  // namespace penumbra
