#include "tools/merge_command.h"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "core/error.h"
#include "film/film_merge.h"

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

}  // namespace penumbra
