#include "tools/merge_command.h"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "core/error.h"
#include "film/film_merge.h"
#include "tools/part_manifest.h"
#include "tools/part_status.h"

namespace penumbra {

int runMergeCommand(const std::vector<std::string>& partNames, const std::string& output, bool noDisplay, bool quiet) {
    std::filesystem::path exrPath(output);
    if (exrPath.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", output));
    std::vector<std::filesystem::path> paths(partNames.begin(), partNames.end());
    MergeResult result = mergeFilmFiles(paths);
    RenderMetadata& m = result.merged.metadata;
    m.version = PENUMBRA_VERSION;
    writeExr(result.merged.film, m, exrPath);
    const std::filesystem::path displayPath = std::filesystem::path(exrPath).replace_extension(".png");
    if (!noDisplay) writeDisplayImage(result.merged.film, displayPath);
    if (!result.uniform)
        std::fprintf(stderr,
                     "penumbra: warning: the merged film does not hold the same samples in every pixel (%s); its "
                     "per-pixel sample counts are right, but it cannot be resumed\n",
                     result.note.c_str());
    if (!quiet) {
        std::printf("merged %zu film%s: %dx%d, samples [%u, %u), pixels %s\n", partNames.size(), partNames.size() == 1 ? "" : "s",
                    result.merged.film.width(), result.merged.film.height(), m.firstSample, m.endSample,
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
        throwFileError(manifestPath,
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
        for (int i = g.firstPart; i < g.endPart; ++i) merger.add(readFilmExr(manifest.parts[size_t(i)].file), manifest.parts[size_t(i)].file.string());
        MergeResult result = merger.finish();
        checkMergedIs(result, manifest, g.firstPart, g.endPart, manifestPath);
        writeMerged(result, output.empty() ? g.file : std::filesystem::path(output), true);
        if (!quiet) std::printf("merged parts %d to %d into %s\n", g.firstPart, g.endPart - 1, g.file.string().c_str());
        return 0;
    }

    const std::filesystem::path exrPath = output.empty() ? manifest.output : std::filesystem::path(output);
    if (exrPath.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", exrPath.string()));
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
