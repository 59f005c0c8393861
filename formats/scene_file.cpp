#include "formats/scene_file.h"

#include <algorithm>
#include <cstdio>
#include <system_error>

#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/resource_paths.h"
#include "formats/pbrt/pbrt_reader.h"
#include "scenes/emitter_orientation.h"
#include "scenes/json_reader.h"
#include "scenes/scene_loader.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

void emitWarnings(const std::vector<std::string>& lines, std::vector<std::string>* sink) {
    for (const std::string& line : lines) {
        if (sink)
            sink->push_back(line);
        else
            std::fprintf(stderr, "penumbra: warning: %s\n", line.c_str());
    }
}

void applyPatch(Json& document, const fs::path& patch) {
    if (patch.empty()) return;
    const Json changes =
        parseJsonText(InputFile(patch, "patch file", limits::kMaxSceneFileBytes).readAll(), patch.string());
    if (!changes.is_object()) throwFileError(patch, "expected a JSON object (a merge patch of the scene)");
    document.merge_patch(changes);
}

// JSON laid out for reading: objects one member a line, arrays of numbers (and arrays of such
// arrays: vertex lists) on one line.
void writeJson(const Json& value, int indent, std::string& out) {
    auto flat = [](const Json& v) {
        if (!v.is_array()) return !v.is_structured();
        for (const Json& e : v)
            if (e.is_object() || (e.is_array() && !std::all_of(e.begin(), e.end(), [](const Json& x) {
                                      return !x.is_structured();
                                  })))
                return false;
        return true;
    };
    const std::string pad(size_t(indent + 4), ' ');
    if (value.is_object() && !value.empty()) {
        out += "{\n";
        size_t i = 0;
        for (const auto& [key, member] : value.items()) {
            out += pad + Json(key).dump() + ": ";
            writeJson(member, indent + 4, out);
            out += ++i < value.size() ? ",\n" : "\n";
        }
        out += std::string(size_t(indent), ' ') + "}";
    } else if (value.is_array() && !flat(value)) {
        out += "[\n";
        for (size_t i = 0; i < value.size(); ++i) {
            out += pad;
            writeJson(value[i], indent + 4, out);
            out += i + 1 < value.size() ? ",\n" : "\n";
        }
        out += std::string(size_t(indent), ' ') + "]";
    } else {
        std::string text = value.dump();
        // nlohmann writes [1,2,3]; a space after each comma reads better.
        std::string spaced;
        bool inString = false;
        for (size_t i = 0; i < text.size(); ++i) {
            const char c = text[i];
            if (c == '"' && (i == 0 || text[i - 1] != '\\')) inString = !inString;
            spaced += c;
            if (c == ',' && !inString) spaced += ' ';
        }
        out += spaced;
    }
}

// A relative scene name that is not found here but is one of the example scenes installed with the
// program (PREFIX/share/penumbra/scenes, where `cmake --install` puts scenes/): the error says where
// they are. Otherwise the readers' own "not found" stands.
void requireSceneOrPointAtExamples(const fs::path& file) {
    std::error_code ec;
    if (!file.is_relative() || fs::exists(file, ec)) return;
    fs::path examples;
    try {
        examples = sharedDataPath("scenes");
    } catch (const InputError&) {
        return;  // no data folder: nothing to point at
    }
    fs::path relative = file;
    if (auto first = relative.begin(); first != relative.end() && *first == "scenes")
        relative = relative.lexically_relative("scenes");
    const fs::path installed = examples / relative;
    if (!fs::is_regular_file(installed, ec)) return;
    SourceLocation where;
    where.file = file.string();
    throw InputError(where, "scene file not found here; the example scenes installed with penumbra are in " +
                                examples.string() + " (this one: " + installed.string() + ")");
}

}  // namespace

bool isPbrtScene(const fs::path& file) {
    const std::string name = file.filename().string();
    return name.ends_with(".pbrt") || name.ends_with(".pbrt.gz");
}

Scene loadSceneFile(const fs::path& file, const SceneFileOptions& options) {
    requireSceneOrPointAtExamples(file);
    Scene scene;
    if (isPbrtScene(file)) {
        pbrt::PbrtConversion conversion = pbrt::convertPbrtFile(file);
        emitWarnings(conversion.warnings, options.warnings);
        applyPatch(conversion.document, options.patch);
        scene = pbrt::buildPbrtScene(conversion, file);
    } else if (options.patch.empty()) {
        scene = loadScene(file);
    } else {
        Json document =
            parseJsonText(InputFile(file, "scene file", limits::kMaxSceneFileBytes).readAll(), file.string());
        applyPatch(document, options.patch);
        scene = buildScene(document, file);
    }
    // The patch is part of the scene: the film's scene hash covers it (resume and merge checks).
    if (!options.patch.empty()) scene.includedFiles.push_back(options.patch);
    emitWarnings(emittersFacingAway(scene), options.warnings);
    return scene;
}

namespace {

// Every "file" key of the document (shapes, prototypes, the environment, image textures) names a
// file relative to `from`: name it relative to `to`.
void rebaseFileNames(Json& value, const fs::path& from, const fs::path& to) {
    if (value.is_array()) {
        for (Json& element : value) rebaseFileNames(element, from, to);
    } else if (value.is_object()) {
        for (auto it = value.begin(); it != value.end(); ++it) {
            Json& member = it.value();
            if (it.key() == "file" && member.is_string()) {
                const fs::path named = fs::path(member.get<std::string>());
                const fs::path absolute = named.is_absolute() ? named : (from / named).lexically_normal();
                const fs::path relative = absolute.lexically_relative(to);
                member = relative.empty() ? absolute.string() : relative.string();
            } else {
                rebaseFileNames(member, from, to);
            }
        }
    }
}

}  // namespace

std::string convertSceneToJson(const fs::path& file, const fs::path& output,
                               std::vector<std::string>* warnings) {
    if (!isPbrtScene(file)) throwFileError(file, "convert reads pbrt-v4 scenes (.pbrt, or .pbrt.gz)");
    pbrt::PbrtConversion conversion = pbrt::convertPbrtFile(file);
    emitWarnings(conversion.warnings, warnings);
    // Check that the scene builds before anything is written.
    (void)pbrt::buildPbrtScene(conversion, file);
    // Files (meshes, images) are named relative to the pbrt file; name them relative to the output.
    const fs::path from = fs::absolute(file).lexically_normal().parent_path(),
                   to = fs::absolute(output).lexically_normal().parent_path();
    rebaseFileNames(conversion.document, from, to);
    return "// Converted from " + file.filename().string() + " by penumbra convert (docs/pbrt-import.md).\n" +
           [&] {
               std::string text;
               writeJson(conversion.document, 0, text);
               return text;
           }() +
           "\n";
}

}  // namespace penumbra
