// Textures on their own: the checkerboard's colours, image lookups through the texture plugin
// (an 8-bit sRGB image linearised by the sRGB formula, a linear image filtered bilinearly, wrap
// modes), the camera footprint against a closed form, and whole images read for environment maps.
#include "textures/texture.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "textures/image_file.h"
#include "textures/texture_footprint.h"
#include "textures/texture_plugin_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

fs::path temporaryFile(const std::string& name) {
    const fs::path folder =
        fs::temp_directory_path() / ("penumbra-texture-test-" + std::to_string(::getpid()));
    fs::create_directories(folder);
    return folder / name;
}

// Writes `pixels` (width x height x channels, rows top to bottom) with OpenImageIO.
template <typename T>
void writeImage(const fs::path& path, int width, int height, int channels, const std::vector<T>& pixels,
                OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(width, height, channels, type);
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(type, pixels.data()));
    ASSERT_TRUE(out->close());
}

TextureQuery at(float u, float v) {
    TextureQuery q;
    q.uv = {u, v};
    return q;
}

ImageTextureSource open(const fs::path& path, TextureFilter filter, TextureWrap wrap = TextureWrap::Repeat) {
    ImageTextureSource source;
    source.plugin = &texturePlugin();
    source.filter = filter;
    source.wrapS = source.wrapT = wrap;
    PenumbraTextureInfo info{};
    char error[512] = "";
    EXPECT_EQ(source.plugin->openTexture(path.c_str(), PENUMBRA_COLOR_AUTO, &source.handle, &info, error,
                                         sizeof error),
              1)
        << error;
    source.channels = info.channels;
    return source;
}

TEST(TextureCheckerboard, ColoursByParityOfTheCells) {
    const Rgb a(0.9f, 0.1f, 0.2f), b(0.05f, 0.3f, 0.7f);
    Texture checker = Texture::checkerboard(a, b);
    checker.mapUv({4.0f, 2.0f}, {0.0f, 0.0f});
    EXPECT_EQ(checker.evaluate(at(0.1f, 0.1f)), a);    // cell (0, 0)
    EXPECT_EQ(checker.evaluate(at(0.3f, 0.1f)), b);    // cell (1, 0)
    EXPECT_EQ(checker.evaluate(at(0.3f, 0.6f)), a);    // cell (1, 1)
    EXPECT_EQ(checker.evaluate(at(-0.1f, 0.1f)), b);   // cell (-1, 0): floor, not truncation
    EXPECT_EQ(checker.evaluate(at(0.99f, 0.99f)), a);  // cell (3, 1)
    EXPECT_EQ(Texture::constant(a).evaluate(at(0.5f, 0.5f)), a);
}

// sRGB's decoding function (IEC 61966-2-1).
double srgbToLinear(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// Every 8-bit code value, looked up at its texel's centre without filtering, is the sRGB formula's
// linear value. The plugin keeps linearised texels as half floats: 11 significant bits, a relative
// error of at most 2^-11 (plus 1e-6 absolute for the smallest values).
TEST(TextureSrgb, EightBitLinearisationMatchesTheSrgbFormula) {
    const int width = 256, height = 1;
    std::vector<unsigned char> pixels(size_t(width) * 3);
    for (int x = 0; x < width; ++x) {
        pixels[3 * size_t(x)] = (unsigned char)x;
        pixels[3 * size_t(x) + 1] = (unsigned char)(255 - x);
        pixels[3 * size_t(x) + 2] = (unsigned char)((x * 7) % 256);
    }
    const fs::path path = temporaryFile("ramp.png");
    writeImage(path, width, height, 3, pixels, OIIO::TypeDesc::UINT8);
    const Texture texture = Texture::image(open(path, TextureFilter::Closest, TextureWrap::Clamp), Rgb(1.0f));
    for (int x = 0; x < width; ++x) {
        const Rgb value = texture.evaluate(at((x + 0.5f) / width, 0.5f));
        for (int c = 0; c < 3; ++c) {
            const double expected = srgbToLinear(pixels[3 * size_t(x) + size_t(c)] / 255.0);
            EXPECT_NEAR(value[c], expected, expected * 0x1p-11 + 1e-6)
                << "code " << int(pixels[3 * size_t(x) + size_t(c)]);
        }
    }
}

// A float image is linear and looked up as it is: bilinear filtering halfway between two texel
// centres gives their mean; the t axis runs down the image (v = 1 is its top row); `invert`.
TEST(TextureImage, LinearImageBilinearAndOrientation) {
    const std::vector<float> pixels = {0.0f, 0.0f, 0.0f, 1.0f,  2.0f,  4.0f,  // top row
                                       8.0f, 8.0f, 8.0f, 16.0f, 16.0f, 16.0f};
    const fs::path path = temporaryFile("linear.exr");
    writeImage(path, 2, 2, 3, pixels, OIIO::TypeDesc::FLOAT);
    const Texture bilinear =
        Texture::image(open(path, TextureFilter::Bilinear, TextureWrap::Clamp), Rgb(1.0f));
    // Texel centres: u = 0.25, 0.75; the top row at v = 0.75.
    EXPECT_EQ(bilinear.evaluate(at(0.75f, 0.75f)), Rgb(1.0f, 2.0f, 4.0f));
    EXPECT_EQ(bilinear.evaluate(at(0.25f, 0.25f)), Rgb(8.0f));
    const Rgb middle = bilinear.evaluate(at(0.5f, 0.75f));
    EXPECT_NEAR(middle.r, 0.5f, 1e-6f);
    EXPECT_NEAR(middle.b, 2.0f, 1e-6f);
    // Black wrap: outside [0, 1) there is nothing.
    const Texture black = Texture::image(open(path, TextureFilter::Closest, TextureWrap::Black), Rgb(1.0f));
    EXPECT_EQ(black.evaluate(at(1.5f, 0.25f)), Rgb(0.0f));
    // Repeat wrap: one period over, the same texel; scale multiplies.
    const Texture repeat = Texture::image(open(path, TextureFilter::Closest, TextureWrap::Repeat), Rgb(2.0f));
    EXPECT_EQ(repeat.evaluate(at(1.25f, 0.25f)), Rgb(16.0f));
    // Inverted (pbrt-v4's invert): 1 minus the scaled texel, at least 0.
    const Texture inverted =
        Texture::image(open(path, TextureFilter::Closest, TextureWrap::Clamp), Rgb(0.25f), true);
    EXPECT_EQ(inverted.evaluate(at(0.75f, 0.75f)), Rgb(0.75f, 0.5f, 0.0f));
    EXPECT_EQ(inverted.evaluate(at(0.25f, 0.25f)), Rgb(0.0f));
    EXPECT_EQ(inverted.coverage(at(0.75f, 0.75f)), 0.75f);
}

// A plane facing a pinhole camera at distance d, uv spanning `size` world units: one pixel covers
// d * spacing world units, so du/dx = d * spacing / size (times the sample scale).
TEST(TextureFootprint, FacingPlaneMatchesPixelSpacing) {
    CameraFootprint camera;
    camera.origin = {0.0f, 0.0f, 0.0f};
    camera.right = {1.0f, 0.0f, 0.0f};
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.pixelSpacing = 0.01f;
    camera.sampleScale = 0.5f;
    const float d = 4.0f, size = 2.0f;
    const TextureQuery q = textureQueryAt(camera, {0.0f, 0.0f, d}, {0.0f, 0.0f, -1.0f}, {0.5f, 0.5f},
                                          {size, 0.0f, 0.0f}, {0.0f, size, 0.0f});
    EXPECT_NEAR(q.dudx, d * 0.01f / size * 0.5f, 1e-6f);
    EXPECT_NEAR(q.dvdy, d * 0.01f / size * 0.5f, 1e-6f);
    EXPECT_NEAR(q.dvdx, 0.0f, 1e-7f);
    EXPECT_NEAR(q.dudy, 0.0f, 1e-7f);
}

// The same under parallel rays (an orthographic camera, pixelSpacing in world units): one pixel
// covers `spacing` world units whatever the distance, and on a plane tilted by 60 degrees about
// the x axis the neighbouring ray one pixel up lands spacing / cos(60) = 2 spacing along it.
TEST(TextureFootprint, ParallelRaysCoverTheSameAreaAtEveryDistance) {
    CameraFootprint camera;
    camera.origin = {0.0f, 0.0f, 0.0f};
    camera.right = {1.0f, 0.0f, 0.0f};
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.parallelDirection = {0.0f, 0.0f, 1.0f};
    camera.pixelSpacing = 0.01f;
    const float size = 2.0f;
    for (float d : {1.0f, 40.0f}) {
        const TextureQuery q = textureQueryAt(camera, {0.3f, 0.2f, d}, {0.0f, 0.0f, -1.0f}, {0.5f, 0.5f},
                                              {size, 0.0f, 0.0f}, {0.0f, size, 0.0f});
        EXPECT_NEAR(q.dudx, 0.01f / size, 1e-6f) << d;
        EXPECT_NEAR(q.dvdy, 0.01f / size, 1e-6f) << d;
    }
    const float c = 0.5f, sn = std::sqrt(3.0f) / 2.0f;  // cos and sin of 60 degrees
    const Vec3f along{0.0f, c, sn};                     // the tilted plane's v direction
    const TextureQuery tilted = textureQueryAt(camera, {0.0f, 0.0f, 5.0f}, {0.0f, -sn, c}, {0.5f, 0.5f},
                                               {size, 0.0f, 0.0f}, along * size);
    EXPECT_NEAR(tilted.dvdy, 2.0f * 0.01f / size, 1e-5f);
    EXPECT_NEAR(tilted.dudx, 0.01f / size, 1e-6f);
}

TEST(TextureImage, UnreadableFileIsAnError) {
    const fs::path path = temporaryFile("garbage.png");
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        std::fputs("not an image", f);
        std::fclose(f);
    }
    void* handle = nullptr;
    PenumbraTextureInfo info{};
    char error[512] = "";
    EXPECT_EQ(
        texturePlugin().openTexture(path.c_str(), PENUMBRA_COLOR_AUTO, &handle, &info, error, sizeof error),
        0);
    EXPECT_GT(std::strlen(error), 0u);
    EXPECT_THROW(readLinearRgbImage(path, SourceLocation{}), InputError);
}

// Whole images for environment maps: OpenEXR read directly, other formats through the plugin.
TEST(TextureImage, ReadsWholeImagesLinear) {
    const std::vector<float> pixels = {0.5f, 1.0f, 2.0f, 100.0f, 200.0f, 300.0f};
    const fs::path exr = temporaryFile("whole.exr");
    writeImage(exr, 2, 1, 3, pixels, OIIO::TypeDesc::FLOAT);
    const LinearRgbImage image = readLinearRgbImage(exr, SourceLocation{});
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 1);
    EXPECT_EQ(image.texels[1], Rgb(100.0f, 200.0f, 300.0f));
    const std::vector<unsigned char> bytes = {0, 128, 255};
    const fs::path png = temporaryFile("whole.png");
    writeImage(png, 1, 1, 3, bytes, OIIO::TypeDesc::UINT8);
    const LinearRgbImage decoded = readLinearRgbImage(png, SourceLocation{});
    EXPECT_NEAR(decoded.texels[0].g, srgbToLinear(128.0 / 255.0), 1e-5);
    EXPECT_NEAR(decoded.texels[0].b, 1.0, 1e-6);
}

// A tiled image read whole through the plugin, a row of tiles at a time (OpenImageIO 2.4's
// scanline reading divides by zero on a tiled TIFF).
TEST(TextureImage, ReadsTiledImagesWhole) {
    const int width = 8, height = 8;
    std::vector<float> pixels(size_t(width) * height * 3);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i);
    const fs::path tif = temporaryFile("tiled.tif");
    auto out = OIIO::ImageOutput::create(tif.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
    spec.tile_width = spec.tile_height = 16;
    ASSERT_TRUE(out->open(tif.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    ASSERT_TRUE(out->close());
    const LinearRgbImage image = readLinearRgbImage(tif, SourceLocation{});
    ASSERT_EQ(image.width, width);
    ASSERT_EQ(image.height, height);
    EXPECT_EQ(
        image.texels[size_t(5 * width + 3)],
        Rgb(pixels[(5 * width + 3) * 3], pixels[(5 * width + 3) * 3 + 1], pixels[(5 * width + 3) * 3 + 2]));
}

// A file forgotten and rewritten under the same name is read again, at its new size (the sRGB
// conversion once read it into a buffer of the old size: OpenImageIO's shared cache kept the
// old header).
TEST(TextureImage, ForgottenFileIsReadAgain) {
    const fs::path path = temporaryFile("rewritten.png");
    writeImage(path, 1, 1, 3, std::vector<unsigned char>{255, 255, 255}, OIIO::TypeDesc::UINT8);
    EXPECT_EQ(Texture::image(open(path, TextureFilter::Closest), Rgb(1.0f)).evaluate(at(0.5f, 0.5f)),
              Rgb(1.0f));
    texturePlugin().forget(path.c_str());
    std::vector<unsigned char> black(8 * 4 * 3, 0);
    writeImage(path, 8, 4, 3, black, OIIO::TypeDesc::UINT8);
    const ImageTextureSource again = open(path, TextureFilter::Closest);
    EXPECT_EQ(Texture::image(again, Rgb(1.0f)).evaluate(at(0.5f, 0.5f)), Rgb(0.0f));
}

// The shipped environment map is what tools/make_sky makes with its defaults, texel for texel.
TEST(EnvironmentSkyMap, ShippedMapIsMakeSkysOutput) {
    const fs::path made = temporaryFile("sky.exr");
    ASSERT_EQ(std::system((std::string(PENUMBRA_MAKE_SKY) + " " + made.string()).c_str()), 0);
    const LinearRgbImage fresh = readLinearRgbImage(made, SourceLocation{});
    const LinearRgbImage shipped =
        readLinearRgbImage(fs::path(PENUMBRA_SOURCE_DIR) / "scenes/textures/sky.exr", SourceLocation{});
    ASSERT_EQ(fresh.width, shipped.width);
    ASSERT_EQ(fresh.height, shipped.height);
    size_t different = 0;
    for (size_t i = 0; i < fresh.texels.size(); ++i) different += !(fresh.texels[i] == shipped.texels[i]);
    EXPECT_EQ(different, 0u);
}

}  // namespace
}  // namespace penumbra
