// Hostile image textures and environment maps end to end: the `penumbra` program must stop with
// "penumbra: error:" naming the file, a non-zero exit status and no output file, within bounded
// memory, where it once read an image whole without a limit (9.6 GB for an 818 KB PNG), rendered
// a truncated texture black, or took NaN and negative radiance for black, all with exit status 0.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using penumbra::testing::RunResult;

const fs::path kHostile = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile";

void appendBigEndian(std::string& out, uint32_t value) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(char((value >> shift) & 0xff));
}

void appendPngChunk(std::string& out, const char* type, const std::string& data) {
    appendBigEndian(out, uint32_t(data.size()));
    const std::string typed = std::string(type, 4) + data;
    out += typed;
    appendBigEndian(out,
                    uint32_t(crc32(0, reinterpret_cast<const Bytef*>(typed.data()), uInt(typed.size()))));
}

// A valid 8-bit grey PNG of one colour, compressed row by row: a 16384 x 16384 one is 300 KB.
std::string oneColourGreyPng(uint32_t side) {
    std::string png = "\x89PNG\r\n\x1a\n";
    std::string header;
    appendBigEndian(header, side);
    appendBigEndian(header, side);
    header += std::string("\x08\x00\x00\x00\x00", 5);  // 8 bits, grey, deflate, adaptive filter, no interlace
    appendPngChunk(png, "IHDR", header);
    z_stream z{};
    deflateInit(&z, 9);
    const std::vector<unsigned char> row(side + 1, 0);  // filter byte 0, then black texels
    std::string compressed;
    std::vector<unsigned char> buffer(1 << 16);
    for (uint32_t y = 0; y < side; ++y) {
        z.next_in = const_cast<unsigned char*>(row.data());
        z.avail_in = uInt(row.size());
        const int flush = y + 1 == side ? Z_FINISH : Z_NO_FLUSH;
        do {
            z.next_out = buffer.data();
            z.avail_out = uInt(buffer.size());
            deflate(&z, flush);
            compressed.append(reinterpret_cast<char*>(buffer.data()), buffer.size() - z.avail_out);
        } while (z.avail_out == 0);
    }
    deflateEnd(&z);
    appendPngChunk(png, "IDAT", compressed);
    appendPngChunk(png, "IEND", "");
    return png;
}

// Writes `pixels` (RGB floats, rows top to bottom) as a scanline OpenEXR file.
void writeExr(const fs::path& path, int width, int height, const std::vector<float>& pixels) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    ASSERT_TRUE(out->close());
}

// The largest resident memory of any child process this test has waited for, in bytes.
uint64_t childrenPeakBytes() {
    rusage usage{};
    getrusage(RUSAGE_CHILDREN, &usage);
    return uint64_t(usage.ru_maxrss) * 1024;
}

class HostileTexture : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-hostile-texture-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "out");
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path writeFile(const std::string& name, const std::string& bytes) {
        const fs::path path = dir_ / name;
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    }
    // A small scene whose floor's albedo is the image texture `image`.
    fs::path texturedScene(const fs::path& image) {
        return writeFile("scene.json",
                         R"({"camera": {"look_from": [0, 3, 6], "look_at": [0, 0, 0], "fov": 40},
  "film": {"resolution": [32, 24], "spp": 2},
  "materials": {"floor": {"type": "lambert", "albedo": {"type": "image", "file": ")" +
                             image.string() + R"("}}},
  "shapes": [{"type": "quad", "corner": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "floor"}],
  "lights": [{"type": "point", "position": [0, 3, 2], "intensity": [10, 10, 10]}]})");
    }
    // A small scene lit by the environment map `image`.
    fs::path environmentScene(const fs::path& image) {
        return writeFile("scene.json",
                         R"({"camera": {"look_from": [0, 3, 6], "look_at": [0, 0, 0], "fov": 40},
  "film": {"resolution": [32, 24], "spp": 2},
  "environment": {"type": "image", "file": ")" +
                             image.string() + R"("},
  "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
  "shapes": [{"type": "quad", "corner": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "grey"}]})");
    }
    // Renders `scene` and checks the failure contract: non-zero exit, an error naming `file`, and
    // nothing in the output folder. A run that hangs is killed after a minute (and fails).
    RunResult expectRenderFailure(const fs::path& scene, const fs::path& file) {
        const RunResult r =
            penumbra::testing::runShell("timeout -s KILL 60 " + std::string(PENUMBRA_BINARY) + " render " +
                                        scene.string() + " -o " + (dir_ / "out" / "image.exr").string());
        EXPECT_GT(r.exitCode, 0) << r.output;
        EXPECT_NE(r.output.find("penumbra: error: "), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(file.string()), std::string::npos)
            << "the error does not name the file: " << r.output;
        EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "an output file was left behind";
        return r;
    }

    fs::path dir_;
};

bool contains(const RunResult& r, const std::string& text) {
    return r.output.find(text) != std::string::npos;
}

TEST_F(HostileTexture, PngBombIsRefusedFromItsHeader) {
    // 16384 x 16384 texels in 300 KB: read whole, once 3.3 GB and 26 s, and 9.6 GB for the RGB one
    // (a SIGSEGV where the allocation failed).
    const fs::path png = writeFile("bomb.png", oneColourGreyPng(16384));
    ASSERT_LT(fs::file_size(png), 400u * 1024);
    const RunResult r = expectRenderFailure(texturedScene(png), png);
    EXPECT_TRUE(contains(r, "/materials/floor/albedo/file: cannot read the image")) << r.output;
    EXPECT_TRUE(contains(r, "16384 x 16384 texels; at most 67108864 are read")) << r.output;
    EXPECT_LT(childrenPeakBytes(), uint64_t(1) << 30);
}

TEST_F(HostileTexture, DeclaredHugeExrTextureIsRefusedFromItsHeader) {
    // declared_9000x9000.exr declares 9000 x 9000 pixels and holds none: once 2.6 GB, a black
    // image and exit status 0.
    const fs::path exr = kHostile / "declared_9000x9000.exr";
    const RunResult r = expectRenderFailure(texturedScene(exr), exr);
    EXPECT_TRUE(contains(r, "9000 x 9000 texels")) << r.output;
    EXPECT_LT(childrenPeakBytes(), uint64_t(1) << 30);
}

TEST_F(HostileTexture, DeclaredHugeEnvironmentMapIsRefusedFromItsHeader) {
    // Read whole as an environment map, it once took 0.96 GB before the missing rows were found.
    const fs::path exr = kHostile / "declared_9000x9000.exr";
    const RunResult r = expectRenderFailure(environmentScene(exr), exr);
    EXPECT_TRUE(contains(r, "/environment/file: " + exr.string() +
                                ": cannot read the OpenEXR image: 14 channels of "
                                "9000 x 9000 texels; at most 536870912 values (texels x channels) are read"))
        << r.output;
    EXPECT_LT(childrenPeakBytes(), uint64_t(256) << 20);
}

TEST_F(HostileTexture, EnvironmentMapDeclaringMoreThanItHoldsTakesMemoryOnlyForWhatDecodes) {
    // 24 bytes that OpenImageIO reads as a 7897 x 14457 RGBA image (found by fuzzing), within the
    // limit of an environment map: its texels were allocated and cleared before the first row
    // failed to decode, 1.9 GB. Now room is reserved, and filled only by rows that decode.
    const fs::path image = kHostile / "declares_7897x14457_in_24_bytes.bmp";
    const RunResult r = expectRenderFailure(environmentScene(image), image);
    EXPECT_TRUE(contains(r, "/environment/file: " + image.string() + ": cannot read the image: "))
        << r.output;
    EXPECT_LT(childrenPeakBytes(), uint64_t(1) << 30);
}

TEST_F(HostileTexture, ExrAttributeDeclaringGigabytesIsRefusedAsTextureAndEnvironment) {
    // OpenEXR's C++ reader allocates what an attribute declares before reading it: 1.8 GB for
    // this 4 KB file. Its headers are parsed by OpenEXR's C core first.
    const fs::path exr = kHostile / "attribute_declares_1_8_gib.exr";
    RunResult r = expectRenderFailure(texturedScene(exr), exr);
    r = expectRenderFailure(environmentScene(exr), exr);
    EXPECT_TRUE(contains(r, "cannot read the OpenEXR image")) << r.output;
    EXPECT_LT(childrenPeakBytes(), uint64_t(1) << 30);
}

// A PNG header declaring `width` x `height` texels, with an empty IDAT (no pixel data).
std::string pngHeader(uint32_t width, uint32_t height) {
    std::string png = "\x89PNG\r\n\x1a\n";
    std::string header;
    appendBigEndian(header, width);
    appendBigEndian(header, height);
    header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filter, no interlace
    appendPngChunk(png, "IHDR", header);
    appendPngChunk(png, "IDAT", "");
    appendPngChunk(png, "IEND", "");
    return png;
}

TEST_F(HostileTexture, ImageWiderThanAnyImageIsRefusedFromItsHeader) {
    // OpenImageIO reads 256 rows at a time whatever the height: a 98-byte BMP declaring
    // 7,107,950 x 4 texels made it ask for 5.4 GB (found by fuzzing). libpng allows 10^6 a side.
    const fs::path png = writeFile("wide.png", pngHeader(100000, 4));
    const RunResult r = expectRenderFailure(texturedScene(png), png);
    EXPECT_TRUE(contains(r, "100000 x 4 texels; at most 65536 a side are read")) << r.output;
}

TEST_F(HostileTexture, FormatsOtherThanTheSevenReadAreRefusedByTheirFirstBytes) {
    // bmp_rle8_of_24_bits.bmp (822 bytes, found by fuzzing): OpenImageIO's BMP reader crashed
    // (SIGSEGV) on it, as texture and as environment map; bmp_7_million_texels_wide.bmp made it ask
    // for 5.4 GB. No file reaches a reader other than OpenEXR's, PNG's, JPEG's, TIFF's, HDR's,
    // PFM's and TGA's.
    for (const char* name : {"bmp_rle8_of_24_bits.bmp", "bmp_7_million_texels_wide.bmp"}) {
        const fs::path bmp = kHostile / name;
        RunResult r = expectRenderFailure(texturedScene(bmp), bmp);
        EXPECT_TRUE(contains(r,
                             "not an image in one of the formats penumbra reads (OpenEXR, PNG, JPEG, TIFF, "
                             "Radiance HDR, PFM, TGA)"))
            << r.output;
        r = expectRenderFailure(environmentScene(bmp), bmp);
        EXPECT_TRUE(contains(r, "not an image in one of the formats penumbra reads")) << r.output;
    }
}

// A 2 x 2 uncompressed 24-bit TGA (bottom-up rows, BGR) and a 2 x 2 PFM (colour, little-endian,
// bottom-up rows), the formats of Tungsten's and pbrt-v4's scenes.
std::string tgaBytes() {
    std::string bytes(18, '\0');
    bytes[2] = 2;                  // uncompressed true colour
    bytes[12] = 2, bytes[14] = 2;  // 2 x 2
    bytes[16] = 24;                // bits per pixel
    for (int i = 0; i < 4; ++i) bytes += std::string("\x40\x80\xc0", 3);
    return bytes;
}
std::string pfmBytes() {
    std::string bytes = "PF\n2 2\n-1.0\n";
    const float value = 0.25f;
    for (int i = 0; i < 12; ++i) bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
    return bytes;
}

TEST_F(HostileTexture, TgaAndPfmImagesAreRead) {
    for (const auto& [name, bytes] :
         {std::pair{std::string("grey.tga"), tgaBytes()}, std::pair{std::string("flat.pfm"), pfmBytes()}}) {
        const fs::path image = writeFile(name, bytes);
        for (const fs::path& scene : {texturedScene(image), environmentScene(image)}) {
            const RunResult r =
                penumbra::testing::runShell(std::string(PENUMBRA_BINARY) + " render " + scene.string() +
                                            " -q -o " + (dir_ / "out" / "image.exr").string());
            EXPECT_EQ(r.exitCode, 0) << name << ": " << r.output;
            EXPECT_TRUE(fs::exists(dir_ / "out" / "image.exr")) << name;
            fs::remove_all(dir_ / "out");
            fs::create_directories(dir_ / "out");
        }
    }
    // TGA has no magic number: a TGA header under another name, and a name .tga over bytes that
    // are no TGA header, reach no reader.
    for (const auto& [name, bytes] : {std::pair{std::string("tga.bmp"), tgaBytes()},
                                      std::pair{std::string("not.tga"), std::string(64, '\x7f')}}) {
        const fs::path image = writeFile(name, bytes);
        const RunResult r = expectRenderFailure(texturedScene(image), image);
        EXPECT_TRUE(contains(r, "not an image in one of the formats penumbra reads")) << r.output;
    }
}

TEST_F(HostileTexture, DisplayWindowLargerThanAnyImageIsRefusedFromItsHeader) {
    // An 8 x 4 EXR of 751 bytes whose display window is 889,192,456 texels wide (found by
    // fuzzing): the TextureSystem spans it and built MIP levels over it, 22 GB and 2.5 minutes.
    const fs::path exr = kHostile / "exr_display_window_889_million_wide.exr";
    const RunResult r = expectRenderFailure(texturedScene(exr), exr);
    EXPECT_TRUE(contains(r, "a display window of 889192456 x 4 texels")) << r.output;
    EXPECT_LT(childrenPeakBytes(), uint64_t(1) << 30);
}

TEST_F(HostileTexture, TruncatedExrTextureStopsTheRender) {
    // Its header reads, so it opens; its pixels are found missing only by the lookups, which once
    // gave black with exit status 0.
    const int side = 256;
    std::vector<float> pixels(size_t(side) * side * 3);
    uint32_t state = 1;
    for (float& p : pixels) p = float((state = state * 1664525u + 1013904223u) >> 8) / float(1 << 24);
    const fs::path whole = dir_ / "whole.exr";
    writeExr(whole, side, side, pixels);
    std::ifstream in(whole, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const fs::path truncated = writeFile("truncated.exr", bytes.substr(0, bytes.size() / 2));
    const RunResult r = expectRenderFailure(texturedScene(truncated), truncated);
    EXPECT_TRUE(contains(r, "cannot read the image texture " + truncated.string() + ": ")) << r.output;
    EXPECT_TRUE(contains(r, "the render stopped")) << r.output;
}

TEST_F(HostileTexture, EnvironmentMapWithNaNIsRefusedNamingTheTexel) {
    std::vector<float> pixels(8 * 4 * 3, 1.0f);
    pixels[(2 * 8 + 5) * 3 + 1] = std::numeric_limits<float>::quiet_NaN();  // G of texel (5, 2)
    const fs::path exr = dir_ / "nan.exr";
    writeExr(exr, 8, 4, pixels);
    const RunResult r = expectRenderFailure(environmentScene(exr), exr);
    EXPECT_TRUE(contains(r, "/environment/file: " + exr.string() + ": texel (5, 2) has G = nan")) << r.output;
}

TEST_F(HostileTexture, EnvironmentMapWithNegativeOrInfiniteRadianceIsRefused) {
    std::vector<float> pixels(8 * 4 * 3, 1.0f);
    pixels[(3 * 8 + 0) * 3 + 2] = -0.5f;                                   // B of texel (0, 3)
    pixels[(3 * 8 + 7) * 3 + 0] = std::numeric_limits<float>::infinity();  // R of texel (7, 3)
    const fs::path exr = dir_ / "negative.exr";
    writeExr(exr, 8, 4, pixels);
    const RunResult r = expectRenderFailure(environmentScene(exr), exr);
    EXPECT_TRUE(contains(r, "texel (0, 3) has B = -0.5")) << r.output;
    EXPECT_TRUE(contains(r, "(2 such values in the image)")) << r.output;
}

}  // namespace
