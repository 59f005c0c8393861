#include "formats/pbrt/parser.h"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string_view>
#include <utility>

#include "core/input_file.h"
#include "core/input_limits.h"
#include "formats/pbrt/spectrum.h"
#include "formats/pbrt/tokenizer.h"

namespace penumbra::pbrt {

namespace fs = std::filesystem;

namespace {

// Include files may include others; a chain deeper than this is surely a cycle.
constexpr int kMaxIncludeDepth = 64;

// What follows a directive's name.
enum class Arguments : uint8_t {
    None,
    Numbers,             // a fixed count of numbers
    Matrix,              // 16 numbers, in brackets or not
    Word,                // one bare word (ActiveTransform StartTime)
    String,              // one quoted string
    StringParams,        // a quoted string and a parameter list (Shape "sphere" ...)
    ThreeStringsParams,  // Texture "name" "spectrum" "imagemap" ...
    Params,              // a parameter list alone (Option)
    OneOrTwoStrings,     // MediumInterface "inside" ["outside"]
    Include,             // Include / Import "file"
};

struct DirectiveShape {
    std::string_view name;
    Arguments arguments;
    int numberCount = 0;
};

constexpr std::array<DirectiveShape, 40> kDirectives{{
    {"Translate", Arguments::Numbers, 3},
    {"Scale", Arguments::Numbers, 3},
    {"Rotate", Arguments::Numbers, 4},
    {"LookAt", Arguments::Numbers, 9},
    {"TransformTimes", Arguments::Numbers, 2},
    {"Transform", Arguments::Matrix},
    {"ConcatTransform", Arguments::Matrix},
    {"Identity", Arguments::None},
    {"ReverseOrientation", Arguments::None},
    {"AttributeBegin", Arguments::None},
    {"AttributeEnd", Arguments::None},
    {"TransformBegin", Arguments::None},
    {"TransformEnd", Arguments::None},
    {"WorldBegin", Arguments::None},
    {"WorldEnd", Arguments::None},
    {"ObjectEnd", Arguments::None},
    {"ActiveTransform", Arguments::Word},
    {"CoordinateSystem", Arguments::String},
    {"CoordSysTransform", Arguments::String},
    {"ObjectBegin", Arguments::String},
    {"ObjectInstance", Arguments::String},
    {"NamedMaterial", Arguments::String},
    {"ColorSpace", Arguments::String},
    {"Camera", Arguments::StringParams},
    {"Film", Arguments::StringParams},
    {"Sampler", Arguments::StringParams},
    {"PixelFilter", Arguments::StringParams},
    {"Integrator", Arguments::StringParams},
    {"Accelerator", Arguments::StringParams},
    {"Shape", Arguments::StringParams},
    {"LightSource", Arguments::StringParams},
    {"AreaLightSource", Arguments::StringParams},
    {"Material", Arguments::StringParams},
    {"MakeNamedMaterial", Arguments::StringParams},
    {"MakeNamedMedium", Arguments::StringParams},
    {"Attribute", Arguments::StringParams},
    {"Texture", Arguments::ThreeStringsParams},
    {"Option", Arguments::Params},
    {"MediumInterface", Arguments::OneOrTwoStrings},
    {"Include", Arguments::Include},
}};

const DirectiveShape* findDirective(std::string_view name) {
    for (const DirectiveShape& d : kDirectives)
        if (d.name == name) return &d;
    if (name == "Import") return &kDirectives.back();  // parsed as Include (see below)
    return nullptr;
}

std::string describe(const Token& t) {
    switch (t.kind) {
        case Token::Kind::End:
            return "the end of the file";
        case Token::Kind::OpenBracket:
            return "'['";
        case Token::Kind::CloseBracket:
            return "']'";
        case Token::Kind::String:
            return fmt::format("the string \"{}\"", t.text);
        case Token::Kind::Word:
            return fmt::format("'{}'", t.text);
    }
    return "?";
}

class Parser {
public:
    Parser(DirectiveTarget& target, std::vector<fs::path>& filesRead, fs::path baseFolder)
        : target_(target), filesRead_(filesRead), baseFolder_(std::move(baseFolder)) {}

    void parseFile(const fs::path& file) {
        InputFile input(file, "scene file", limits::kMaxSceneFileBytes);
        firstReading(input);
        const std::string text = readText(input, file);
        distinctBytes_ += text.size();
        filesRead_.push_back(file);
        parseText(text, file, 0);
    }

    // Scene text given in memory: as a file read for the first time.
    void parseTextOnce(std::string_view text, const fs::path& file) {
        distinctBytes_ += text.size();
        parseText(text, file, 0);
    }

    void parseText(std::string_view text, const fs::path& file, int depth) {
        ++fileReads_;
        textBytes_ += text.size();
        target_.textRead(textBytes_);
        Tokenizer tokens(text, file.string());
        while (true) {
            const Token t = tokens.next();
            if (t.kind == Token::Kind::End) return;
            if (t.kind != Token::Kind::Word)
                tokens.fail(t, fmt::format("expected a directive (such as Shape or AttributeBegin), found {}",
                                           describe(t)));
            const DirectiveShape* shape = findDirective(t.text);
            if (!shape) tokens.fail(t, fmt::format("unknown directive '{}'", t.text));
            Directive d;
            d.name = std::string(t.text);
            d.where = tokens.locationOf(t);
            readArguments(tokens, *shape, d);
            if (shape->arguments == Arguments::Include) {
                include(tokens, t, d, depth);
                continue;
            }
            target_.directive(std::move(d));
        }
    }

private:
    void include(Tokenizer& tokens, const Token& at, const Directive& d, int depth) {
        const fs::path name = d.strings[0];
        if (name.empty()) tokens.fail(at, fmt::format("{} needs a file name", d.name));
        const fs::path path = name.is_absolute() ? name : baseFolder_ / name;
        if (depth + 1 > kMaxIncludeDepth)
            tokens.fail(at, fmt::format("{} nests deeper than {} files (does a file include itself?)", d.name,
                                        kMaxIncludeDepth));
        std::error_code error;
        if (!fs::exists(path, error))
            tokens.fail(at, fmt::format("{}: file \"{}\" not found (looked for {})", d.name, name.string(),
                                        path.string()));
        // A file may include another many times, and each of those many more: without these
        // bounds a few small files could ask for 10^12 readings.
        if (fileReads_ >= limits::kMaxPbrtFileReads)
            tokens.fail(
                at,
                fmt::format("{} \"{}\" would be file reading {} of this scene: a pbrt scene reads at most {} "
                            "files, each Include or Import counted every time it is read (docs/limits.md)",
                            d.name, name.string(), fileReads_ + 1, limits::kMaxPbrtFileReads));
        InputFile input(path, "scene file", limits::kMaxSceneFileBytes);
        const bool first = firstReading(input);
        const std::string text = readText(input, path);
        if (textBytes_ + text.size() > limits::kMaxPbrtTextBytes)
            tokens.fail(
                at, fmt::format(
                        "{} \"{}\" ({}) would bring the text read for this scene to {}: a pbrt scene reads "
                        "at most {} of text, each Include or Import counted every time it is read "
                        "(docs/limits.md)",
                        d.name, name.string(), describeBytes(text.size()),
                        describeBytes(textBytes_ + text.size()), describeBytes(limits::kMaxPbrtTextBytes)));
        // Reading a file again adds nothing to the input, but the scene made of it grows (to about
        // nine times the text): as much text again as the distinct files hold, or a little.
        if (first) {
            distinctBytes_ += text.size();
        } else {
            const uint64_t allowed = std::max(limits::kMinPbrtRereadBytes, distinctBytes_);
            if (rereadBytes_ + text.size() > allowed)
                tokens.fail(
                    at, fmt::format(
                            "{} \"{}\" ({}, read before) would bring the text read again to {}: a pbrt scene "
                            "reads its files again for at most {}, as much as its distinct files hold ({}) "
                            "or {} if that is more (docs/limits.md)",
                            d.name, name.string(), describeBytes(text.size()),
                            describeBytes(rereadBytes_ + text.size()), describeBytes(allowed),
                            describeBytes(distinctBytes_), describeBytes(limits::kMinPbrtRereadBytes)));
            rereadBytes_ += text.size();
        }
        filesRead_.push_back(path);
        parseText(text, path, depth + 1);
    }

    // Whether this is the first reading of the file (by device and inode: "b.pbrt" and
    // "./b.pbrt" are one file); the first counts towards the distinct files' text. Asked before
    // the file is read (a gzip reading closes it).
    bool firstReading(const InputFile& input) {
        struct stat status {};
        return ::fstat(input.fd(), &status) == 0 && filesSeen_.insert({status.st_dev, status.st_ino}).second;
    }

    // The file's text, decompressed when its name ends in ".gz" (as pbrt-v4 reads it). It
    // outlives the tokens made of it: directives copy what they keep.
    static std::string readText(InputFile& input, const fs::path& file) {
        return file.extension() == ".gz" ? input.readAllGzip() : input.readAll();
    }

    double number(Tokenizer& tokens, const Token& t) {
        if (t.kind != Token::Kind::Word)
            tokens.fail(t, fmt::format("expected a number, found {}", describe(t)));
        double value = 0.0;
        const char* first = t.text.data();
        const char* last = first + t.text.size();
        if (first != last && *first == '+') ++first;  // from_chars does not take a leading '+'
        const auto [end, ec] = std::from_chars(first, last, value);
        if (ec != std::errc() || end != last || !std::isfinite(value))
            tokens.fail(t, fmt::format("expected a number, found '{}'", t.text));
        return value;
    }

    std::string string(Tokenizer& tokens, const Token& t, std::string_view what) {
        if (t.kind != Token::Kind::String)
            tokens.fail(t, fmt::format("expected {} in quotes, found {}", what, describe(t)));
        return tokens.stringValue(t);
    }

    void readArguments(Tokenizer& tokens, const DirectiveShape& shape, Directive& d) {
        switch (shape.arguments) {
            case Arguments::None:
                return;
            case Arguments::Numbers:
                for (int i = 0; i < shape.numberCount; ++i)
                    d.numbers.push_back(number(tokens, tokens.next()));
                return;
            case Arguments::Matrix: {
                const bool bracketed = tokens.peek().kind == Token::Kind::OpenBracket;
                if (bracketed) tokens.next();
                for (int i = 0; i < 16; ++i) {
                    const Token t = tokens.next();
                    if (bracketed && t.kind == Token::Kind::CloseBracket)
                        tokens.fail(t, fmt::format("{} needs 16 numbers, found {}", d.name, i));
                    d.numbers.push_back(number(tokens, t));
                }
                if (bracketed) {
                    const Token t = tokens.next();
                    if (t.kind != Token::Kind::CloseBracket)
                        tokens.fail(t, fmt::format("{} needs 16 numbers and then ']', found {}", d.name,
                                                   describe(t)));
                }
                return;
            }
            case Arguments::Word: {
                const Token t = tokens.next();
                if (t.kind != Token::Kind::Word)
                    tokens.fail(t, fmt::format("{} expected a word, found {}", d.name, describe(t)));
                d.strings.emplace_back(t.text);
                return;
            }
            case Arguments::String:
            case Arguments::Include:
                d.strings.push_back(string(tokens, tokens.next(), "a name"));
                return;
            case Arguments::OneOrTwoStrings:
                d.strings.push_back(string(tokens, tokens.next(), "a medium name"));
                if (tokens.peek().kind == Token::Kind::String)
                    d.strings.push_back(tokens.stringValue(tokens.next()));
                return;
            case Arguments::StringParams:
                d.strings.push_back(string(tokens, tokens.next(), "a type name"));
                d.parameters = readParameters(tokens);
                return;
            case Arguments::ThreeStringsParams:
                d.strings.push_back(string(tokens, tokens.next(), "a texture name"));
                d.strings.push_back(
                    string(tokens, tokens.next(), "the texture's type (\"float\" or \"spectrum\")"));
                d.strings.push_back(string(tokens, tokens.next(), "the texture's class"));
                d.parameters = readParameters(tokens);
                return;
            case Arguments::Params:
                d.parameters = readParameters(tokens);
                return;
        }
    }

    // "type name" followed by one value or a bracketed list of values, repeated.
    ParameterList readParameters(Tokenizer& tokens) {
        std::vector<Parameter> parameters;
        while (tokens.peek().kind == Token::Kind::String) {
            const Token declaration = tokens.next();
            const std::string quoted = tokens.stringValue(declaration);
            // pbrt-v4 skips white space around the type and the name: the official bunny-fur scene
            // declares " float beta_n".
            constexpr const char* kSpace = " \t\r\n";
            const size_t first = quoted.find_first_not_of(kSpace), last = quoted.find_last_not_of(kSpace);
            const std::string text = first == std::string::npos ? "" : quoted.substr(first, last - first + 1);
            Parameter p;
            p.where = tokens.locationOf(declaration);
            const size_t space = text.find_first_of(kSpace);
            const size_t nameStart =
                space == std::string::npos ? std::string::npos : text.find_first_not_of(kSpace, space);
            if (nameStart == std::string::npos || text.find_first_of(kSpace, nameStart) != std::string::npos)
                tokens.fail(
                    declaration,
                    fmt::format("expected a parameter declaration \"TYPE NAME\", found \"{}\"", quoted));
            const std::string typeName = text.substr(0, space);
            const std::optional<ParamType> type = paramTypeFromName(typeName);
            if (!type)
                tokens.fail(
                    declaration,
                    fmt::format("unknown parameter type '{}' in \"{}\" (expected integer, float, point2, "
                                "vector2, point3, vector3, normal, bool, string, texture, rgb, "
                                "blackbody or spectrum)",
                                typeName, text));
            p.type = *type;
            p.name = text.substr(nameStart);
            readValues(tokens, declaration, p);
            parameters.push_back(std::move(p));
        }
        return ParameterList(std::move(parameters));
    }

    void readValue(Tokenizer& tokens, const Token& t, const Token& declaration, Parameter& p) {
        switch (p.type) {
            case ParamType::Bool:
                if (t.text == "true")
                    p.bools.push_back(1);
                else if (t.text == "false")
                    p.bools.push_back(0);
                else
                    tokens.fail(t, fmt::format("parameter \"{}\" expects true or false, found {}",
                                               p.declaration(), describe(t)));
                return;
            case ParamType::String:
            case ParamType::Texture:
                if (t.kind != Token::Kind::String)
                    tokens.fail(t, fmt::format("parameter \"{}\" expects a string in quotes, found {}",
                                               p.declaration(), describe(t)));
                p.strings.push_back(tokens.stringValue(t));
                return;
            case ParamType::Spectrum:
                // Either (wavelength, value) pairs or the name of a named spectrum or a file.
                if (t.kind == Token::Kind::String)
                    p.strings.push_back(tokens.stringValue(t));
                else
                    p.numbers.push_back(number(tokens, t));
                return;
            default:
                if (t.kind != Token::Kind::Word)
                    tokens.fail(t, fmt::format("parameter \"{}\" expects numbers, found {}", p.declaration(),
                                               describe(t)));
                p.numbers.push_back(number(tokens, t));
                if (p.type == ParamType::Integer && p.numbers.back() != std::floor(p.numbers.back()))
                    tokens.fail(t, fmt::format("parameter \"{}\" expects integers, found '{}'",
                                               p.declaration(), t.text));
                // pbrt-v4 stores integer parameters as int: beyond its range a value has no meaning
                // (and would not convert to an integer type exactly).
                if (p.type == ParamType::Integer && std::abs(p.numbers.back()) > double(INT32_MAX))
                    tokens.fail(t, fmt::format("parameter \"{}\" expects integers within +-{}, found '{}'",
                                               p.declaration(), INT32_MAX, t.text));
                (void)declaration;
        }
    }

    void readValues(Tokenizer& tokens, const Token& declaration, Parameter& p) {
        const Token first = tokens.next();
        if (first.kind == Token::Kind::OpenBracket) {
            while (true) {
                const Token t = tokens.next();
                if (t.kind == Token::Kind::CloseBracket) break;
                // A directive's name inside the brackets: the ']' was forgotten.
                const bool directive = t.kind == Token::Kind::Word && findDirective(t.text);
                if (t.kind == Token::Kind::End || t.kind == Token::Kind::OpenBracket || directive)
                    tokens.fail(
                        t,
                        fmt::format(
                            "the values of parameter \"{}\" (opened with '[' at line {}) need a closing ']', "
                            "found {}",
                            p.declaration(), first.line, describe(t)));
                readValue(tokens, t, declaration, p);
            }
        } else if (first.kind == Token::Kind::End || first.kind == Token::Kind::CloseBracket) {
            tokens.fail(first, fmt::format("parameter \"{}\" has no value", p.declaration()));
        } else {
            readValue(tokens, first, declaration, p);
        }
        const size_t count = p.numbers.size() + p.strings.size() + p.bools.size();
        if (count == 0)
            tokens.fail(declaration, fmt::format("parameter \"{}\" has no value", p.declaration()));
        const int per = valuesPerElement(p.type);
        if (per > 1 && p.numbers.size() % size_t(per) != 0)
            tokens.fail(declaration, fmt::format("parameter \"{}\" needs a multiple of {} numbers, found {}",
                                                 p.declaration(), per, p.numbers.size()));
        if (p.type == ParamType::Spectrum && !p.strings.empty() && !p.numbers.empty())
            tokens.fail(declaration,
                        fmt::format("parameter \"{}\" mixes a name and numbers", p.declaration()));
        if (p.type == ParamType::Spectrum && p.numbers.size() % 2 != 0)
            tokens.fail(declaration,
                        fmt::format("parameter \"{}\" needs (wavelength, value) pairs, found {} numbers",
                                    p.declaration(), p.numbers.size()));
        if (p.type == ParamType::Spectrum && p.strings.size() == 1 && !namedSpectrumRgb(p.strings[0]))
            readSpectrumFile(tokens, declaration, p);
    }

    // pbrt-v4 reads a spectrum parameter's string that names no named spectrum as a file of
    // (wavelength, value) pairs, relative to the scene's folder: its pairs replace the name. Each
    // file is read once per scene.
    void readSpectrumFile(Tokenizer& tokens, const Token& declaration, Parameter& p) {
        const fs::path name = p.strings[0];
        const fs::path path = name.is_absolute() ? name : baseFolder_ / name;
        auto known = spectrumFiles_.find(path);
        if (known == spectrumFiles_.end()) {
            std::error_code error;
            if (name.empty() || !fs::exists(path, error))
                tokens.fail(
                    declaration,
                    fmt::format(
                        "parameter \"{}\": \"{}\" is neither a named spectrum (penumbra knows the "
                        "metal-{{Cu,Au,Ag,Al}}-{{eta,k}}, glass-{{BK7,BAF10,FK51A,LASF9,F5,F10,F11}}, "
                        "stdillum-D65 and stdillum-A spectra) nor a spectrum file (looked for {})",
                        p.declaration(), name.string(), path.string()));
            InputFile input(path, "spectrum file", limits::kMaxSpectrumFileBytes);
            known = spectrumFiles_.emplace(path, parseSpectrumFile(input.readAll(), path.string())).first;
            filesRead_.push_back(path);
        }
        p.strings.clear();
        p.numbers = known->second;
    }

    DirectiveTarget& target_;
    std::vector<fs::path>& filesRead_;
    fs::path baseFolder_;
    std::map<fs::path, std::vector<double>> spectrumFiles_;  // read so far, by path
    int fileReads_ = 0;
    uint64_t textBytes_ = 0;  // every reading
    std::set<std::pair<dev_t, ino_t>> filesSeen_;
    uint64_t distinctBytes_ = 0, rereadBytes_ = 0;  // the first readings, and the later ones
};

}  // namespace

void parseSceneFile(const fs::path& file, DirectiveTarget& target, std::vector<fs::path>& filesRead) {
    Parser parser(target, filesRead, file.parent_path());
    parser.parseFile(file);
}

void parseSceneText(std::string_view text, const fs::path& file, DirectiveTarget& target,
                    std::vector<fs::path>& filesRead) {
    Parser parser(target, filesRead, file.parent_path());
    parser.parseTextOnce(text, file);
}

}  // namespace penumbra::pbrt
