// pbrt-v4 scenes crafted to cost far more than their size (tests/data/hostile/pbrt-bombs, or built
// here when large): Include fan-out, object instances of many shapes, deep nesting. Each is refused
// at the directive that crosses its limit (core/input_limits.h), quickly, with a message naming
// the limit; and the reader's other hostile cases: CR-only line ends, generated names that collide
// with the scene's own, a crop window beyond the integers.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>

#include "core/error.h"
#include "core/input_limits.h"
#include "formats/pbrt/pbrt_reader.h"
#include "formats/scene_file.h"
#include "scenes/scene_loader.h"

namespace penumbra::pbrt {
namespace {

namespace fs = std::filesystem;

const fs::path kBombs = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile" / "pbrt-bombs";
const std::string kHeader =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n"
    "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\nWorldBegin\n";

// Each bomb once took from 0.8 s (nesting) to forever (fan-out); refused, each takes milliseconds.
// The bound is generous for a loaded machine.
constexpr double kRefusedWithinSeconds = 5.0;

// Runs `read`, which must throw InputError; returns its message, and fails the test when it took
// longer than `withinSeconds`.
std::string refusal(const std::function<void()>& read, double withinSeconds = kRefusedWithinSeconds) {
    const auto start = std::chrono::steady_clock::now();
    std::string message;
    try {
        read();
        ADD_FAILURE() << "read without an error";
    } catch (const InputError& e) {
        message = e.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, withinSeconds) << message;
    return message;
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// A folder of this test's own, removed at its end.
class PbrtBombFolder : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-pbrt-bomb-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& text) {
        std::ofstream(dir_ / name, std::ios::binary) << text;
        return dir_ / name;
    }
    fs::path dir_;
};

TEST(PbrtBombs, IncludeFanOutIsRefusedAtTheFileReadingPastTheLimit) {
    // 13 files of 10 Includes each (6.5 KB): 10^12 readings; once 2.5 GB after 20 s, and going on.
    const fs::path main = kBombs / "include-fan-out" / "main.pbrt";
    const std::string message = refusal([&] { convertPbrtFile(main); });
    EXPECT_TRUE(contains(message, "include-fan-out/f1")) << message;  // the Include's file
    EXPECT_TRUE(contains(message, ":1: Include \"f")) << message;     // ... its first line
    EXPECT_TRUE(contains(
        message, fmt::format("would be file reading {} of this scene", limits::kMaxPbrtFileReads + 1)))
        << message;
    EXPECT_TRUE(
        contains(message, fmt::format("a pbrt scene reads at most {} files", limits::kMaxPbrtFileReads)))
        << message;
}

TEST_F(PbrtBombFolder, IncludedTextIsBoundedAcrossTheScene) {
    // Four distinct files of 256 MiB each (a comment: "#" and zero bytes, sparse on the disk), the
    // most a scene file may have: within every file's limit, 1 GiB and more in all.
    std::string main = kHeader;
    for (const char* name : {"a.pbrt", "b.pbrt", "c.pbrt", "d.pbrt"}) {
        const fs::path file = write(name, "#");
        fs::resize_file(file, limits::kMaxSceneFileBytes);
        main += fmt::format("Include \"{}\"\n", name);
    }
    const fs::path scene = write("main.pbrt", main);
    // Three of them are read first (768 MiB, 2.5 s here): no bound on the time but the test's.
    const std::string message = refusal([&] { convertPbrtFile(scene); }, 600.0);
    EXPECT_TRUE(contains(
        message,
        "main.pbrt:8:1: Include \"d.pbrt\" (256.0 MiB) would bring the text read for this scene to 1.0 GiB"))
        << message;
    EXPECT_TRUE(contains(message, "a pbrt scene reads at most 1.0 GiB of text")) << message;
}

TEST_F(PbrtBombFolder, FilesReadAgainAreBoundedByTheDistinctText) {
    // A 64 KiB file included 300 times (under any name of it): 19 MiB of text from 70 KB.
    write("small.pbrt", "#" + std::string(65535, 'x'));
    std::string main = kHeader;
    for (int i = 0; i < 300; ++i) main += i % 2 ? "Include \"small.pbrt\"\n" : "Include \"./small.pbrt\"\n";
    const std::string message = refusal([&] { convertPbrtFile(write("main.pbrt", main)); });
    // The first reading and 256 more make 16 MiB read again; the 258th Include is refused.
    EXPECT_TRUE(contains(
        message,
        fmt::format("main.pbrt:{}:1: Include \"small.pbrt\" (65536 bytes, read before) would bring the "
                    "text read again to 16.1 MiB",
                    4 + 258)))
        << message;
    EXPECT_TRUE(contains(message, "reads its files again for at most 16.0 MiB")) << message;

    // A file as large as what is read again is read twice, not three times.
    const fs::path big = write("big.pbrt", "#");
    fs::resize_file(big, uint64_t(40) << 20);
    EXPECT_NO_THROW(
        convertPbrtFile(write("twice.pbrt", kHeader + "Include \"big.pbrt\"\nInclude \"big.pbrt\"\n")));
    const std::string thrice = refusal([&] {
        convertPbrtFile(write("thrice.pbrt",
                              kHeader + "Include \"big.pbrt\"\nImport \"big.pbrt\"\nImport \"big.pbrt\"\n"));
    });
    EXPECT_TRUE(contains(thrice, "thrice.pbrt:7:1: Import \"big.pbrt\"")) << thrice;
}

TEST(PbrtBombs, InstancesOfManySpheresAreRefusedAtTheLimit) {
    // An object of 1000 spheres placed 1000 times (74 KB): once 10^6 sphere copies, 12 s, 1.8 GB,
    // and a 360 MiB JSON file that `penumbra render` refuses to read.
    std::string text = kHeader + "ObjectBegin \"a\"\n";
    for (int i = 0; i < 1000; ++i) text += "Translate 0.001 0 0\nShape \"sphere\" \"float radius\" 0.01\n";
    text += "ObjectEnd\n";
    for (int i = 0; i < 1000; ++i) text += "ObjectInstance \"a\"\n";
    const std::string message = refusal([&] { convertPbrtText(text, "spheres.pbrt"); });
    // 65 instances place 65,000 spheres; the 66th would pass 2^16.
    const int line = 4 + 1 + 2000 + 1 + 66;
    EXPECT_TRUE(contains(
        message,
        fmt::format("spheres.pbrt:{}:1: ObjectInstance \"a\" would bring the shapes placed by object "
                    "instances to 66000 (it places 1000)",
                    line)))
        << message;
    EXPECT_TRUE(contains(message, "places at most 65536, one per 16 bytes of text and at least 65536"))
        << message;
}

TEST(PbrtBombs, InstancesOfManyMeshesAreRefusedAtTheLimit) {
    // An object of 2000 one-triangle meshes placed 2000 times (142 KB): 4 * 10^6 instances through
    // JSON matrices; once std::bad_alloc at 4 GB after 13 s (5 GB and growing without a limit).
    std::string text = kHeader + "ObjectBegin \"a\"\n";
    for (int i = 0; i < 2000; ++i) text += "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n";
    text += "ObjectEnd\n";
    for (int i = 0; i < 2000; ++i) text += "ObjectInstance \"a\"\n";
    const std::string message = refusal([&] { convertPbrtText(text, "meshes.pbrt"); });
    const int line = 4 + 1 + 2000 + 1 + 33;  // 32 instances place 64,000 meshes
    EXPECT_TRUE(contains(message, fmt::format("meshes.pbrt:{}:1: ObjectInstance \"a\" would bring", line)))
        << message;
    EXPECT_TRUE(contains(message, "places at most 65536")) << message;
}

TEST(PbrtBombs, ACopiedMeshCountsItsTriangles) {
    // An emitting mesh is copied at each instance (instances do not emit): 10^4 triangles placed
    // seven times pass 2^16.
    std::string mesh = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [";
    for (int i = 0; i < 10000; ++i) mesh += "0 1 2 ";
    mesh += "]\n";
    std::string text = kHeader + "ObjectBegin \"lamp\"\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n" +
                       mesh + "ObjectEnd\n";
    for (int i = 0; i < 7; ++i) text += "ObjectInstance \"lamp\"\n";
    const std::string message = refusal([&] { convertPbrtText(text, "lamp.pbrt"); });
    EXPECT_TRUE(
        contains(message,
                 "lamp.pbrt:15:1: ObjectInstance \"lamp\" would bring the shapes placed by object instances "
                 "to 70000 (it places 10000)"))
        << message;
}

TEST(PbrtBombs, InstancesWithinTheLimitArePlaced) {
    // The limit grows with the text: 2^16 placements, and one per 16 bytes beyond.
    std::string text = kHeader + "ObjectBegin \"a\"\n";
    for (int i = 0; i < 100; ++i) text += "Shape \"sphere\" \"float radius\" 0.01\n";
    text += "ObjectEnd\n";
    for (int i = 0; i < 655; ++i) text += "ObjectInstance \"a\"\n";  // 65,500 spheres
    const PbrtConversion c = convertPbrtText(text, "within.pbrt");
    EXPECT_EQ(c.document["shapes"].size(), 65500u);
    // 2 MiB of comments allow 131072.
    const std::string comments(size_t(2) << 20, '#');
    for (int i = 0; i < 655; ++i) text += "ObjectInstance \"a\"\n";
    EXPECT_EQ(convertPbrtText(text + comments, "within.pbrt").document["shapes"].size(), 131000u);
}

TEST(PbrtBombs, DeepNestingIsRefusedAtTheLevelPastTheLimit) {
    // 10^6 AttributeBegin (15 MB): once 500 MB before the error at the end of the file.
    std::string text = kHeader;
    for (int i = 0; i < 1000000; ++i) text += (i % 3 == 2 ? "TransformBegin\n" : "AttributeBegin\n");
    const std::string message = refusal([&] { convertPbrtText(text, "deep.pbrt"); });
    const int line = 4 + limits::kMaxPbrtNesting + 1;
    EXPECT_TRUE(contains(message, fmt::format("deep.pbrt:{}:1: AttributeBegin would open level {} of nesting",
                                              line, limits::kMaxPbrtNesting + 1)))
        << message;
    EXPECT_TRUE(contains(message, fmt::format("at most {} levels deep", limits::kMaxPbrtNesting))) << message;
    // As deep as the limit is allowed, ObjectBegin counted too.
    std::string deep = kHeader + "ObjectBegin \"o\"\n";
    for (int i = 1; i < limits::kMaxPbrtNesting; ++i) deep += "AttributeBegin\n";
    for (int i = 1; i < limits::kMaxPbrtNesting; ++i) deep += "AttributeEnd\n";
    EXPECT_NO_THROW(convertPbrtText(deep + "ObjectEnd\n", "deep.pbrt"));
    EXPECT_THROW(convertPbrtText(deep + "AttributeBegin\n", "deep.pbrt"), InputError);
}

// Each Texture naming the one before twice would double the texture at every line (2^60 values at
// line 60): refused at the line whose texture crosses the bound, of nesting or of size.
TEST(PbrtBombs, TexturesOfTexturesAreBounded) {
    std::string doubling = kHeader + "Texture \"t0\" \"float\" \"fbm\"\n";
    for (int i = 1; i <= 60; ++i)
        doubling += fmt::format(
            "Texture \"t{}\" \"float\" \"mix\" \"texture tex1\" \"t{}\" \"texture tex2\" \"t{}\"\n", i, i - 1,
            i - 1);
    std::string message = refusal([&] { convertPbrtText(doubling, "doubling.pbrt"); });
    EXPECT_TRUE(contains(message, "doubling.pbrt:")) << message;
    EXPECT_TRUE(contains(message, fmt::format("hold at most {} values", limits::kMaxPbrtTextureValues)))
        << message;
    // A chain of single inputs: refused at the level past 16.
    std::string chain = kHeader + "Texture \"t0\" \"float\" \"windy\"\n";
    for (int i = 1; i <= 40; ++i)
        chain += fmt::format(
            "Texture \"t{}\" \"float\" \"scale\" \"texture tex\" \"t0\" \"texture scale\" \"t{}\"\n", i,
            i - 1);
    message = refusal([&] { convertPbrtText(chain, "chain.pbrt"); });
    EXPECT_TRUE(contains(message, "chain.pbrt:22:1: texture \"t17\"")) << message;
    // 16 levels of inputs below the top are allowed, as the JSON reader allows them.
    std::string allowed = kHeader + "Texture \"t0\" \"float\" \"windy\"\n";
    for (int i = 1; i <= 16; ++i)
        allowed += fmt::format(
            "Texture \"t{}\" \"float\" \"scale\" \"texture tex\" \"t{}\" \"float scale\" 2\n", i, i - 1);
    allowed += "Material \"diffuse\" \"texture displacement\" \"t16\"\nShape \"sphere\"\n";
    const PbrtConversion c = convertPbrtText(allowed, "allowed.pbrt");
    EXPECT_NO_THROW(buildScene(c.document, "allowed.pbrt"));
}

TEST(PbrtBombs, ALoneCarriageReturnEndsAComment) {
    // pbrt-v4 ends a comment at CR too: a CR-only file once was one long comment (a black image,
    // exit 0). Lines are counted at lone CRs, so the error is at the line an editor shows.
    const fs::path file = kBombs / "cr-only-lines.pbrt";
    const std::string message = refusal([&] { convertPbrtFile(file); });
    EXPECT_TRUE(contains(message, file.string() + ":9:1: sphere: the radius must be > 0")) << message;

    const std::string scene = "# camera\r" + kHeader +
                              "# light\rLightSource \"point\" \"rgb I\" [1 1 1]\r# shape\r" +
                              "Shape \"sphere\"\r";
    std::string crOnly = scene;
    for (char& c : crOnly)
        if (c == '\n') c = '\r';
    const PbrtConversion c = convertPbrtText(crOnly, "cr.pbrt");
    EXPECT_EQ(c.document["shapes"].size(), 1u);
    EXPECT_EQ(c.document["lights"].size(), 1u);
    EXPECT_EQ(c.document["film"]["resolution"], Json::array({16, 16}));
    // CR LF is one line end, a string cannot span a lone CR.
    try {
        convertPbrtText("# a\r\n#b\r\nShape \"sphere\r\"\n", "crlf.pbrt");
        ADD_FAILURE() << "a string across a CR was read";
    } catch (const InputError& e) {
        EXPECT_TRUE(contains(e.what(), "crlf.pbrt:3:7: unterminated string")) << e.what();
    }
}

// The prototype each instance shape places, by the z of its first vertex (the scenes below tell
// their meshes apart by z).
std::multiset<double> placedZ(const Json& document) {
    std::multiset<double> z;
    for (const Json& shape : document["shapes"])
        if (shape["type"] == "instance")
            z.insert(document["prototypes"][shape["prototype"].get<std::string>()]["positions"][0][2]
                         .get<double>());
    return z;
}

TEST(PbrtBombs, ObjectNamesDoNotCollideWithTheNamesOfOtherObjectsShapes) {
    // Object "a/0" and the first shape of object "a" were both prototype "a/0": one replaced the
    // other (a black image where it should be, exit 0).
    const PbrtConversion c = convertPbrtFile(kBombs / "object-name-collision.pbrt");
    EXPECT_EQ(c.document["prototypes"].size(), 3u) << c.document["prototypes"].dump();
    EXPECT_EQ(placedZ(c.document), (std::multiset<double>{0.0, 1.0, 2.0}));
    // The other order, and a third object taking the renamed one's name.
    const PbrtConversion d = convertPbrtText(
        kHeader +
            "ObjectBegin \"a\"\nShape \"trianglemesh\" \"point3 P\" [0 0 1  1 0 1  0 1 1]\n"
            "Shape \"trianglemesh\" \"point3 P\" [0 0 2  1 0 2  0 1 2]\nObjectEnd\n"
            "ObjectBegin \"a/0\"\nShape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0]\nObjectEnd\n"
            "ObjectBegin \"a/0#2\"\nShape \"trianglemesh\" \"point3 P\" [0 0 3  1 0 3  0 1 3]\nObjectEnd\n"
            "ObjectInstance \"a\"\nObjectInstance \"a/0\"\nObjectInstance \"a/0#2\"\nObjectInstance "
            "\"a/0\"\n",
        "names.pbrt");
    EXPECT_EQ(d.document["prototypes"].size(), 4u) << d.document["prototypes"].dump();
    EXPECT_EQ(placedZ(d.document), (std::multiset<double>{0.0, 0.0, 1.0, 2.0, 3.0}));
}

TEST(PbrtBombs, MaterialNamesDoNotCollideWithGeneratedOnes) {
    // A named material called as the converter calls pbrt's default material, or an anonymous
    // Material, once replaced it (or was replaced).
    const PbrtConversion c =
        convertPbrtText(kHeader +
                            "Shape \"sphere\"\n"
                            "MakeNamedMaterial \"pbrt default (diffuse 0.5)\" \"string type\" \"conductor\"\n"
                            "Material \"dielectric\"\n"
                            "MakeNamedMaterial \"Material at m.pbrt:7:1\" \"string type\" \"diffuse\" "
                            "\"rgb reflectance\" [0.1 0.2 0.3]\n"
                            "NamedMaterial \"pbrt default (diffuse 0.5)\"\nShape \"sphere\"\n",
                        "m.pbrt");
    const Json& materials = c.document["materials"];
    EXPECT_EQ(materials.size(), 4u) << materials.dump();
    EXPECT_EQ(materials["pbrt default (diffuse 0.5)"]["type"], "lambert");
    EXPECT_EQ(materials["Material at m.pbrt:7:1"]["type"], "dielectric");
    EXPECT_EQ(c.document["shapes"][1]["material"], "pbrt default (diffuse 0.5)#2");
    EXPECT_EQ(materials["pbrt default (diffuse 0.5)#2"]["type"], "conductor");
}

TEST(PbrtBombs, ACropWindowOutsideTheImageIsRefused) {
    // [0 1e30 0 1] once converted 16e30 to int for the warning: undefined behaviour.
    const fs::path file = kBombs / "cropwindow-beyond-integers.pbrt";
    const std::string message = refusal([&] { convertPbrtFile(file); });
    EXPECT_TRUE(contains(
        message,
        file.string() + ":2:62: Film cropwindow: expected fractions of the image from 0 to 1, found 1e+30"))
        << message;
    // Within the image, in either order (as pbrt-v4 takes it): the scene's crop window (its pixels:
    // tests/tools/production_cli_test.cpp).
    const PbrtConversion c = convertPbrtText(
        "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 50 \"float cropwindow\" [0.5 0.25 "
        "0 0.999]\nWorldBegin\n",
        "crop.pbrt");
    EXPECT_EQ(c.document["film"]["crop_window"], Json::array({0.25, 0.5, 0.0, 0.999}));
    const Scene scene = buildPbrtScene(c, "crop.pbrt");
    ASSERT_TRUE(scene.film.cropWindow);
    EXPECT_EQ(scene.film.cropWindow->at(3), 0.999f);
}

TEST(PbrtBombs, ValuesTheLoaderRefusesAreReportedAtTheirDirective) {
    // Values beyond penumbra's limits were reported at a JSON pointer of the translation only
    // (no line in the pbrt file); two negative sample counts made a positive one.
    auto messageOf = [](const std::string& text) {
        try {
            const PbrtConversion c = convertPbrtText(text, "v.pbrt");
            buildPbrtScene(c, "v.pbrt");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_TRUE(
        contains(messageOf("Integrator \"path\" \"integer maxdepth\" 5000\nWorldBegin\n"), "v.pbrt:1:1: "));
    // 65536^2 samples a pixel, from the second of two Samplers.
    EXPECT_TRUE(contains(messageOf("Sampler \"halton\"\nSampler \"stratified\" \"integer xsamples\" 65536 "
                                   "\"integer ysamples\" 65536\nWorldBegin\n"),
                         "v.pbrt:2:1: "));
    EXPECT_TRUE(
        contains(messageOf("PixelFilter \"box\" \"float xradius\" 1000 \"float yradius\" 1000\nWorldBegin\n"),
                 "v.pbrt:1:1: "));
    EXPECT_TRUE(contains(messageOf("Camera \"perspective\" \"float lensradius\" 1e30\nWorldBegin\n"),
                         "v.pbrt:1:1: "));
    EXPECT_TRUE(contains(
        messageOf("Sampler \"stratified\" \"integer xsamples\" -2 \"integer ysamples\" -2\nWorldBegin\n"),
        "v.pbrt:1:1: Sampler \"stratified\": expected xsamples and ysamples of at least 1, found -2 and -2"));
}

TEST(PbrtBombs, NegativeRoughnessAndInnerRadiusAreRefused) {
    // Both were taken silently as 0: a smooth conductor, a whole disk.
    auto messageOf = [](const std::string& text) {
        try {
            convertPbrtText(kHeader + text, "r.pbrt");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_TRUE(contains(messageOf("Material \"conductor\" \"float roughness\" -1\nShape \"sphere\"\n"),
                         "r.pbrt:5:22: parameter \"float roughness\" must be >= 0, found -1"));
    EXPECT_TRUE(contains(messageOf("Material \"dielectric\" \"float vroughness\" -0.5\nShape \"sphere\"\n"),
                         "r.pbrt:5:23: parameter \"float vroughness\" must be >= 0, found -0.5"));
    EXPECT_TRUE(
        contains(messageOf("Shape \"disk\" \"float innerradius\" -1\n"),
                 "r.pbrt:5:1: disk: the inner radius must be from 0 to below the radius (1), found -1"));
}

}  // namespace
}  // namespace penumbra::pbrt
