#include "formats/pbrt/pbrt_reader.h"

#include <fmt/format.h>

#include "scenes/scene_loader.h"

namespace penumbra::pbrt {

namespace fs = std::filesystem;

namespace {

PbrtConversion finish(SceneBuilder& builder, WarningLog& log, std::vector<fs::path> files) {
    PbrtConversion out;
    out.document = builder.finish();
    out.origins = builder.origins();
    out.files = std::move(files);
    out.warnings = log.lines();
    return out;
}

// The origin whose pointer is the longest prefix of `pointer` (at a token boundary).
const Origin* originOf(const std::vector<Origin>& origins, std::string_view pointer) {
    const Origin* best = nullptr;
    for (const Origin& o : origins) {
        const bool prefix = pointer.substr(0, o.pointer.size()) == o.pointer &&
                            (pointer.size() == o.pointer.size() || pointer[o.pointer.size()] == '/');
        // Of equal ones the last: a directive given twice (Film, Sampler) counts as it is last given.
        if (prefix && (!best || o.pointer.size() >= best->pointer.size())) best = &o;
    }
    return best;
}

}  // namespace

PbrtConversion convertPbrtFile(const fs::path& file) {
    WarningLog log;
    SceneBuilder builder(file, log);
    std::vector<fs::path> files;
    parseSceneFile(file, builder, files);
    return finish(builder, log, std::move(files));
}

PbrtConversion convertPbrtText(std::string_view text, const fs::path& file) {
    WarningLog log;
    SceneBuilder builder(file, log);
    std::vector<fs::path> files;
    parseSceneText(text, file, builder, files);
    return finish(builder, log, std::move(files));
}

Scene buildPbrtScene(const PbrtConversion& conversion, const fs::path& file) {
    try {
        Scene scene = buildScene(conversion.document, file);
        scene.includedFiles.assign(conversion.files.begin() + (conversion.files.empty() ? 0 : 1),
                                   conversion.files.end());
        return scene;
    } catch (const InputError& e) {
        const SourceLocation& where = e.where();
        if (where.file == file.string() && !where.jsonPointer.empty()) {
            if (const Origin* origin = originOf(conversion.origins, where.jsonPointer))
                throw InputError(origin->where, fmt::format("{} (at {} of the scene as penumbra reads it)",
                                                            e.message(), where.jsonPointer));
        }
        // A mesh file's error names the shape by its pointer: name the directive instead.
        std::string message = e.message();
        const std::string marker = file.string() + ": /shapes/";
        if (const size_t at = message.find(marker); at != std::string::npos) {
            const size_t end = message.find_first_of(")", at);
            const std::string pointer =
                message.substr(at + file.string().size() + 2, end - at - file.string().size() - 2);
            if (const Origin* origin = originOf(conversion.origins, pointer))
                message.replace(at, end - at, "Shape at " + origin->where.describe());
            throw InputError(where, message);
        }
        throw;
    }
}

}  // namespace penumbra::pbrt
