// The grammar of pbrt-v4 scenes (formats/pbrt/tokenizer.h, parameter_list.h, parser.h): tokens and
// their places, every parameter type with and without brackets, each directive's arguments, and
// Include / Import.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/input_limits.h"
#include "formats/pbrt/parser.h"
#include "formats/pbrt/tokenizer.h"
#include "formats/pbrt/warning_log.h"
#include "formats/scene_file.h"

namespace penumbra::pbrt {
namespace {

namespace fs = std::filesystem;

struct Recorder : DirectiveTarget {
    std::vector<Directive> directives;
    void directive(Directive&& d) override { directives.push_back(std::move(d)); }
};

std::vector<Directive> parse(const std::string& text) {
    Recorder r;
    std::vector<fs::path> files;
    parseSceneText(text, "test.pbrt", r, files);
    return r.directives;
}

TEST(PbrtTokenizer, CommentsStringsBracketsAndPlaces) {
    const std::string text = "# a comment\n  Shape \"sph\\\"ere\" [ 1.5 -2e3 ] # trailing\n\"x\"";
    Tokenizer t(text, "f.pbrt");
    Token a = t.next();
    EXPECT_EQ(a.kind, Token::Kind::Word);
    EXPECT_EQ(a.text, "Shape");
    EXPECT_EQ(a.line, 2);
    EXPECT_EQ(a.column, 3);
    Token s = t.next();
    EXPECT_EQ(s.kind, Token::Kind::String);
    EXPECT_EQ(t.stringValue(s), "sph\"ere");
    EXPECT_EQ(t.next().kind, Token::Kind::OpenBracket);
    EXPECT_EQ(t.next().text, "1.5");
    EXPECT_EQ(t.next().text, "-2e3");
    EXPECT_EQ(t.next().kind, Token::Kind::CloseBracket);
    Token x = t.next();
    EXPECT_EQ(x.line, 3);
    EXPECT_EQ(x.column, 1);
    EXPECT_EQ(t.next().kind, Token::Kind::End);
}

TEST(PbrtTokenizer, EscapesAndErrors) {
    Tokenizer t("\"a\\tb\\\\c\\n\"", "f.pbrt");
    EXPECT_EQ(t.stringValue(t.next()), "a\tb\\c\n");
    Tokenizer bad("Shape \"open\n\"", "f.pbrt");
    bad.next();
    EXPECT_THROW(bad.next(), InputError);
    const std::string withControl = "Shape \x01";  // the tokenizer views the text: it must outlive it
    Tokenizer control(withControl, "f.pbrt");
    control.next();
    EXPECT_THROW(control.next(), InputError);
}

TEST(PbrtParameters, EveryTypeWithAndWithoutBrackets) {
    const auto d = parse(
        "Shape \"x\" \"integer a\" [1 2] \"float b\" 2.5 \"point2 c\" [1 2] \"vector2 d\" [3 4] \"point3 e\" "
        "[1 2 3]\n"
        "  \"vector3 f\" [4 5 6] \"normal g\" [0 0 1] \"bool h\" true \"bool i\" [false] \"string j\" \"s\"\n"
        "  \"texture k\" \"tex\" \"rgb l\" [0.1 0.2 0.3] \"blackbody m\" 5500 \"spectrum n\" "
        "\"metal-Cu-eta\"\n"
        "  \"spectrum o\" [400 0.5 700 0.7] \"point p\" [1 1 1] \"vector q\" [2 2 2] \"normal3 r\" [0 1 0] "
        "\"color s\" [1 1 1]");
    ASSERT_EQ(d.size(), 1u);
    const ParameterList& p = d[0].parameters;
    EXPECT_EQ(p.getInts("a"), (std::vector<int64_t>{1, 2}));
    EXPECT_EQ(*p.getFloat("b"), 2.5);
    ASSERT_EQ(p.getPoint2s("c").size(), 1u);
    EXPECT_EQ(p.getPoint2s("c")[0].y, 2.0);
    EXPECT_EQ(p.find("d", {ParamType::Vector2})->numbers, (std::vector<double>{3, 4}));
    EXPECT_EQ(p.getPoint3s("e")[0].z, 3.0);
    EXPECT_EQ(p.getPoint3("f")->x, 4.0);
    EXPECT_EQ(p.getNormals("g")[0].z, 1.0);
    EXPECT_TRUE(*p.getBool("h"));
    EXPECT_FALSE(*p.getBool("i"));
    EXPECT_EQ(*p.getString("j"), "s");
    EXPECT_EQ(p.find("k", {ParamType::Texture})->strings[0], "tex");
    EXPECT_EQ(p.find("l", {ParamType::Rgb})->numbers[2], 0.3);
    EXPECT_EQ(p.find("m", {ParamType::Blackbody})->numbers[0], 5500.0);
    EXPECT_EQ(p.find("n", {ParamType::Spectrum})->strings[0], "metal-Cu-eta");
    EXPECT_EQ(p.find("o", {ParamType::Spectrum})->numbers.size(), 4u);
    EXPECT_EQ(p.find("p", {ParamType::Point3})->numbers.size(), 3u);
    EXPECT_EQ(p.find("q", {ParamType::Vector3})->numbers.size(), 3u);
    EXPECT_EQ(p.find("r", {ParamType::Normal})->numbers.size(), 3u);
    EXPECT_EQ(p.find("s", {ParamType::Rgb})->numbers.size(), 3u);
    // Asking with the wrong type is an error at the parameter's place.
    try {
        p.getFloat("j");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.where().line, 2);
        EXPECT_NE(std::string(e.what()).find("wrong type"), std::string::npos);
    }
}

// pbrt-v4 skips white space around a declaration's type and name: the official bunny-fur scene
// declares " float beta_n". A declaration is still two words.
TEST(PbrtParameters, WhiteSpaceAroundTheTypeAndNameIsSkipped) {
    const auto d =
        parse("Shape \"x\" \" float beta_n\" 0.3 \"\\tinteger  levels \" 2 \"point3\\nP\" [1 2 3]");
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(*d[0].parameters.getFloat("beta_n"), 0.3);
    EXPECT_EQ(*d[0].parameters.getInt("levels"), 2);
    EXPECT_EQ(d[0].parameters.getPoint3s("P").size(), 1u);
    for (const char* bad : {"\" float \"", "\"float a b\"", "\"  \""}) try {
            parse(std::string("Shape \"x\" ") + bad + " 1");
            ADD_FAILURE() << bad << " was read";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("expected a parameter declaration \"TYPE NAME\""),
                      std::string::npos)
                << e.what();
        }
}

TEST(PbrtParameters, UnusedAreReportedWithCounts) {
    const auto d = parse("Shape \"x\" \"float used\" 1 \"float unused\" 2\nShape \"x\" \"float unused\" 3");
    WarningLog log;
    for (const Directive& directive : d) {
        directive.parameters.getFloat("used");
        directive.parameters.reportUnused(log, "Shape \"x\"");
    }
    const auto lines = log.lines();
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0],
              "test.pbrt:1:26: parameter \"float unused\" of Shape \"x\" is not supported and was ignored (2 "
              "times)");
}

TEST(PbrtParser, EveryDirectiveShape) {
    const auto d = parse(
        "LookAt 0 0 5 0 0 0 0 1 0\nTranslate 1 2 3\nScale -1 1 1\nRotate 90 0 1 0\n"
        "Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\nConcatTransform 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
        "CoordinateSystem \"a\"\nCoordSysTransform \"a\"\nActiveTransform StartTime\nTransformTimes 0 1\n"
        "Identity\nReverseOrientation\nCamera \"perspective\" \"float fov\" 45\nFilm \"rgb\"\nSampler "
        "\"halton\"\n"
        "PixelFilter \"box\"\nIntegrator \"path\"\nAccelerator \"bvh\"\nColorSpace \"srgb\"\nOption \"bool "
        "x\" true\n"
        "WorldBegin\nAttributeBegin\nAttributeEnd\nTransformBegin\nTransformEnd\nObjectBegin "
        "\"o\"\nObjectEnd\n"
        "ObjectInstance \"o\"\nMaterial \"diffuse\"\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
        "NamedMaterial \"m\"\nTexture \"t\" \"spectrum\" \"constant\" \"rgb value\" [1 1 1]\n"
        "LightSource \"point\"\nAreaLightSource \"diffuse\"\nShape \"sphere\"\nMakeNamedMedium \"fog\"\n"
        "MediumInterface \"fog\" \"\"\nMediumInterface \"fog\"\nAttribute \"shape\" \"float radius\" "
        "2\nWorldEnd\n");
    ASSERT_EQ(d.size(), 40u);
    EXPECT_EQ(d[0].name, "LookAt");
    EXPECT_EQ(d[0].numbers.size(), 9u);
    EXPECT_EQ(d[4].numbers.size(), 16u);
    EXPECT_EQ(d[5].numbers.size(), 16u);
    EXPECT_EQ(d[8].strings[0], "StartTime");
    EXPECT_EQ(d[31].strings, (std::vector<std::string>{"t", "spectrum", "constant"}));
    EXPECT_EQ(d[36].strings.size(), 2u);
    EXPECT_EQ(d[37].strings.size(), 1u);
    EXPECT_EQ(d[12].where.line, 13);
    EXPECT_EQ(d[12].where.column, 1);
}

TEST(PbrtParser, IncludeAndImportReadFilesRelativeToTheSceneFile) {
    const fs::path dir = fs::temp_directory_path() / "penumbra_pbrt_include_test";
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "sub" / "part.pbrt") << "Shape \"sphere\"\n";
    std::ofstream(dir / "sub" / "other.pbrt") << "Shape \"disk\"\n";
    std::ofstream(dir / "main.pbrt") << "WorldBegin\nInclude \"sub/part.pbrt\"\nImport \"sub/other.pbrt\"\n";
    Recorder r;
    std::vector<fs::path> files;
    parseSceneFile(dir / "main.pbrt", r, files);
    ASSERT_EQ(r.directives.size(), 3u);
    EXPECT_EQ(r.directives[1].strings[0], "sphere");
    EXPECT_EQ(r.directives[1].where.file, (dir / "sub" / "part.pbrt").string());
    EXPECT_EQ(r.directives[2].strings[0], "disk");
    ASSERT_EQ(files.size(), 3u);
    EXPECT_EQ(files[0], dir / "main.pbrt");
    fs::remove_all(dir);
}

void writeGzip(const fs::path& file, const std::string& text) {
    gzFile gz = gzopen(file.c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    ASSERT_EQ(gzwrite(gz, text.data(), unsigned(text.size())), int(text.size()));
    ASSERT_EQ(gzclose(gz), Z_OK);
}

// Scenes ship their big meshes as gzip-compressed includes (pbrt-v4 reads any file whose name ends
// in ".gz" so); a truncated one is an error naming it, and one that inflates beyond the scene-file
// limit stops there.
TEST(PbrtParser, GzipCompressedIncludesAreDecompressed) {
    const fs::path dir = fs::temp_directory_path() / "penumbra_pbrt_gzip_test";
    fs::create_directories(dir);
    writeGzip(dir / "geometry.pbrt.gz", "Shape \"sphere\"\n# a comment\nShape \"disk\"\n");
    std::ofstream(dir / "main.pbrt") << "WorldBegin\nImport \"geometry.pbrt.gz\"\n";
    Recorder r;
    std::vector<fs::path> files;
    parseSceneFile(dir / "main.pbrt", r, files);
    ASSERT_EQ(r.directives.size(), 3u);
    EXPECT_EQ(r.directives[2].strings[0], "disk");
    EXPECT_EQ(r.directives[2].where.file, (dir / "geometry.pbrt.gz").string());
    EXPECT_EQ(r.directives[2].where.line, 3);
    // The main file too, which the renderer takes for a pbrt scene by its name.
    writeGzip(dir / "whole.pbrt.gz", "WorldBegin\nShape \"sphere\"\n");
    Recorder whole;
    parseSceneFile(dir / "whole.pbrt.gz", whole, files);
    EXPECT_EQ(whole.directives.size(), 2u);
    EXPECT_TRUE(isPbrtScene(dir / "whole.pbrt.gz"));
    EXPECT_FALSE(isPbrtScene(dir / "mesh.ply.gz"));

    // A download cut short: the first half of a gzip stream.
    writeGzip(dir / "broken.pbrt.gz", std::string(4000, '#') + "\nShape \"sphere\"\n");
    fs::resize_file(dir / "broken.pbrt.gz", fs::file_size(dir / "broken.pbrt.gz") / 2);
    std::ofstream(dir / "broken.pbrt") << "WorldBegin\nInclude \"broken.pbrt.gz\"\n";
    try {
        parseSceneFile(dir / "broken.pbrt", r, files);
        ADD_FAILURE() << "a corrupt gzip file was read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("broken.pbrt.gz: cannot decompress the gzip data"),
                  std::string::npos)
            << e.what();
    }

    // Zeros compress about a thousandfold: a 0.3 MiB file that inflates past 256 MiB.
    {
        gzFile gz = gzopen((dir / "bomb.pbrt.gz").c_str(), "wb9");
        ASSERT_NE(gz, nullptr);
        const std::string zeros(1 << 20, ' ');
        for (uint64_t written = 0; written <= limits::kMaxSceneFileBytes; written += zeros.size())
            ASSERT_EQ(gzwrite(gz, zeros.data(), unsigned(zeros.size())), int(zeros.size()));
        ASSERT_EQ(gzclose(gz), Z_OK);
    }
    EXPECT_LT(fs::file_size(dir / "bomb.pbrt.gz"), uint64_t(1) << 20);
    std::ofstream(dir / "bomb.pbrt") << "WorldBegin\nInclude \"bomb.pbrt.gz\"\n";
    try {
        parseSceneFile(dir / "bomb.pbrt", r, files);
        ADD_FAILURE() << "a gzip bomb was read";
    } catch (const InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("bomb.pbrt.gz: the scene file decompresses to more than 256.0 MiB"),
            std::string::npos)
            << e.what();
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace penumbra::pbrt
