#include "tools/status_command.h"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "tools/part_manifest.h"
#include "tools/part_status.h"

namespace fs = std::filesystem;

namespace penumbra {

int runStatusCommand(const std::string& outputOrManifest) {
    const fs::path given(outputOrManifest);
    const fs::path manifestPath = given.extension() == ".json" ? given : manifestPathFor(given);
    if (!fs::exists(manifestPath))
        throw InputError(fmt::format("{}: no manifest (written by penumbra submit) for this output",
                                     manifestPath.string()));
    const PartManifest m = readManifest(manifestPath);
    int counts[5] = {};
    uint64_t samplesDone = 0, samplesAll = 0;
    for (size_t i = 0; i < m.parts.size(); ++i) {
        const RenderPart& part = m.parts[i];
        const PartStatus status = partStatus(m, part);
        ++counts[int(status.state)];
        const uint64_t pixels =
            part.crop ? uint64_t(part.crop->width()) * part.crop->height() : uint64_t(m.width) * m.height;
        samplesAll += pixels * (part.endSample - part.firstSample);
        if (status.state == PartState::Done) samplesDone += pixels * (part.endSample - part.firstSample);
        if (status.state == PartState::Partial) samplesDone += pixels * (status.heldEnd - part.firstSample);
        std::printf("part %4zu  %-22s %s\n", i, describePart(part).c_str(),
                    describeStatus(part, status).c_str());
    }
    const bool merged = fs::exists(m.output);
    std::printf("%zu parts: %d done, %d partial, %d started, %d missing%s; %.1f%% of the samples in files\n",
                m.parts.size(), counts[int(PartState::Done)], counts[int(PartState::Partial)],
                counts[int(PartState::Started)], counts[int(PartState::Missing)],
                counts[int(PartState::Foreign)]
                    ? fmt::format(", {} not their part's film", counts[int(PartState::Foreign)]).c_str()
                    : "",
                samplesAll ? 100.0 * double(samplesDone) / double(samplesAll) : 0.0);
    if (counts[int(PartState::Done)] == int(m.parts.size()))
        std::printf(
            "%s\n",
            merged
                ? fmt::format("merged: {}", m.output.string()).c_str()
                : fmt::format("not merged yet: penumbra merge --manifest {}", manifestPath.string()).c_str());
    return 0;
}

}  // namespace penumbra
