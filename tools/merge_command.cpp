#include "tools/merge_command.h"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "film/display_image.h"
#include "film/film_exr.h"
#include "film/film_merge.h"
#include "tools/part_manifest.h"
#include "tools/part_status.h"

namespace fs = std::filesystem;

namespace penumbra {

namespace {

// A merge never writes over one of the films it reads.
void requireNotAnInput(const fs::path& output, const std::vector<fs::path>& inputs) {
    std::error_code ec;
    for (const fs::path& input : inputs)
        if (fs::equivalent(output, input, ec))
            throw InputError(fmt::format("-o: {} is one of the films being merged ({}); name another output",
                                         output.string(), input.string()));
}

// What `merge --manifest` writes (the output, a group's film) may replace an earlier penumbra film
// but no other file: a file there that is not a film is someone's, and is kept.
void requireFilmOrNothing(const fs::path& output) {
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(output, ec))) return;
    try {
        readFilmHeader(output);
    } catch (const InputError& e) {
        throw InputError(
            fmt::format("{} exists and is not a penumbra film ({}); it is not overwritten: move it away",
                        output.string(), e.what()));
    }
}

}  // namespace

int runMergeCommand(const std::vector<std::string>& partNames, const std::string& output, bool noDisplay,
                    bool quiet) {
    std::filesystem::path exrPath(output);
    if (exrPath.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", output));
    std::vector<std::filesystem::path> paths(partNames.begin(), partNames.end());
    requireNotAnInput(exrPath, paths);
    MergeResult result = mergeFilmFiles(paths);
    RenderMetadata& m = result.merged.metadata;
    m.version = PENUMBRA_VERSION;
    writeExr(result.merged.film, m, exrPath);
    const std::filesystem::path displayPath = std::filesystem::path(exrPath).replace_extension(".png");
    if (!noDisplay) writeDisplayImage(result.merged.film, displayPath);
    if (!result.uniform)
        std::fprintf(
            stderr,
            "penumbra: warning: the merged film does not hold the same samples in every pixel (%s); its "
            "per-pixel sample counts are right, but it cannot be resumed\n",
            result.note.c_str());
    if (!quiet) {
        std::printf("merged %zu film%s: %dx%d, samples [%u, %u), pixels %s\n", partNames.size(),
                    partNames.size() == 1 ? "" : "s", result.merged.film.width(), result.merged.film.height(),
                    m.firstSample, m.endSample,
                    describeWindow(m.crop.value_or(PixelWindow{0, result.merged.film.width(), 0,
                                                               result.merged.film.height()}))
                        .c_str());
        std::printf("wrote %s\n", exrPath.string().c_str());
        if (!noDisplay) std::printf("wrote %s\n", displayPath.string().c_str());
    }
    return 0;
}

namespace {

// The union the merged film must be: parts [firstPart, endPart) of the manifest, bit for bit one
// render of it (FilmMerger checks the rest: same render, no overlaps).
void checkMergedIs(const MergeResult& result, const PartManifest& manifest, int firstPart, int endPart,
                   const std::string& manifestPath) {
    const RenderPart expected = unionOfParts(manifest, firstPart, endPart);
    const RenderMetadata& m = result.merged.metadata;
    if (!result.uniform || m.firstSample != expected.firstSample || m.endSample != expected.endSample ||
        m.crop != expected.crop)
        throwFileError(
            manifestPath,
            fmt::format("the merged parts {} to {} hold samples {} of pixels {}{}, not {} as listed; "
                        "nothing written",
                        firstPart, endPart - 1, describeRange(m),
                        describeWindow(m.crop.value_or(PixelWindow{0, manifest.width, 0, manifest.height})),
                        result.uniform ? "" : " (" + result.note + ")", describePart(expected)));
}

bool groupFileHolds(const PartManifest& manifest, const MergeGroup& group) {
    RenderPart asPart = unionOfParts(manifest, group.firstPart, group.endPart);
    asPart.file = group.file;
    return partStatus(manifest, asPart).state == PartState::Done;
}

// Every film a manifest's merges read: the parts and the merge groups' films.
std::vector<fs::path> inputsOf(const PartManifest& manifest) {
    std::vector<fs::path> inputs;
    for (const RenderPart& p : manifest.parts) inputs.push_back(p.file);
    for (const MergeGroup& g : manifest.groups) inputs.push_back(g.file);
    return inputs;
}

void writeMerged(MergeResult& result, const std::filesystem::path& exrPath, bool noDisplay) {
    result.merged.metadata.version = PENUMBRA_VERSION;
    writeExr(result.merged.film, result.merged.metadata, exrPath);
    if (!noDisplay)
        writeDisplayImage(result.merged.film, std::filesystem::path(exrPath).replace_extension(".png"));
}

}  // namespace

int runManifestMerge(const std::string& manifestPath, std::optional<int> group, const std::string& output,
                     bool noDisplay, bool quiet) {
    const PartManifest manifest = readManifest(manifestPath);
    requireAllPartsDone(manifest, manifestPath);
    FilmMerger merger;
    if (group) {
        if (*group < 0 || size_t(*group) >= manifest.groups.size())
            throw InputError(fmt::format("--group: the manifest has merge groups 0 to {}, not {}",
                                         int(manifest.groups.size()) - 1, *group));
        const MergeGroup& g = manifest.groups[size_t(*group)];
        const fs::path groupPath = output.empty() ? g.file : fs::path(output);
        std::vector<fs::path> inputs;
        for (int i = g.firstPart; i < g.endPart; ++i) inputs.push_back(manifest.parts[size_t(i)].file);
        requireNotAnInput(groupPath, inputs);
        requireFilmOrNothing(groupPath);
        for (const fs::path& part : inputs) merger.add(readFilmExr(part), part.string());
        MergeResult result = merger.finish();
        checkMergedIs(result, manifest, g.firstPart, g.endPart, manifestPath);
        writeMerged(result, groupPath, true);
        if (!quiet)
            std::printf("merged parts %d to %d into %s\n", g.firstPart, g.endPart - 1,
                        g.file.string().c_str());
        return 0;
    }

    const std::filesystem::path exrPath = output.empty() ? manifest.output : std::filesystem::path(output);
    if (exrPath.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", exrPath.string()));
    requireNotAnInput(exrPath, inputsOf(manifest));
    requireFilmOrNothing(exrPath);
    // A merge group's film stands for its parts when it holds exactly their samples; otherwise
    // (not merged yet, or from before a resubmit) its parts are merged directly.
    size_t films = 0;
    std::vector<bool> covered(manifest.parts.size(), false);
    for (const MergeGroup& g : manifest.groups)
        if (groupFileHolds(manifest, g)) {
            merger.add(readFilmExr(g.file), g.file.string());
            ++films;
            for (int i = g.firstPart; i < g.endPart; ++i) covered[size_t(i)] = true;
        }
    for (size_t i = 0; i < manifest.parts.size(); ++i)
        if (!covered[i]) {
            merger.add(readFilmExr(manifest.parts[i].file), manifest.parts[i].file.string());
            ++films;
        }
    MergeResult result = merger.finish();
    checkMergedIs(result, manifest, 0, int(manifest.parts.size()), manifestPath);
    writeMerged(result, exrPath, noDisplay);
    if (!quiet) {
        std::printf("merged %zu parts (%zu films): %dx%d, samples %s\n", manifest.parts.size(), films,
                    result.merged.film.width(), result.merged.film.height(),
                    describeRange(result.merged.metadata).c_str());
        std::printf("wrote %s\n", exrPath.string().c_str());
    }
    return 0;
}

}  // namespace penumbra
