#include "tools/part_status.h"

#include <fmt/format.h>

#include <chrono>

#include "core/error.h"
#include "film/film_exr.h"
#include "film/film_merge.h"

namespace fs = std::filesystem;

namespace penumbra {

namespace {

double secondsSinceWrite(const fs::path& path) {
    std::error_code ec;
    const auto written = fs::last_write_time(path, ec);
    if (ec) return 0;
    return std::chrono::duration<double>(fs::file_time_type::clock::now() - written).count();
}

}  // namespace

fs::path partLogPath(const RenderPart& part) {
    return part.file.parent_path() / "logs" / part.file.filename().replace_extension(".log");
}

PartStatus partStatus(const PartManifest& manifest, const RenderPart& part) {
    PartStatus status;
    std::error_code ec;
    if (!fs::exists(part.file, ec)) {
        const fs::path log = partLogPath(part);
        if (fs::exists(log, ec)) {
            status.state = PartState::Started;
            status.secondsSinceWrite = secondsSinceWrite(log);
        }
        return status;
    }
    status.secondsSinceWrite = secondsSinceWrite(part.file);
    FilmHeader header;
    try {
        header = readFilmHeader(part.file);
    } catch (const InputError& e) {
        status.state = PartState::Foreign;
        status.problem = e.what();
        return status;
    }
    const RenderMetadata& m = header.metadata;
    const PixelWindow full{0, manifest.width, 0, manifest.height};
    const PixelWindow window = m.crop.value_or(full), expected = part.crop.value_or(full);
    status.state = PartState::Foreign;
    if (header.width != manifest.width || header.height != manifest.height)
        status.problem = fmt::format("it is {}x{}, the render {}x{}", header.width, header.height,
                                     manifest.width, manifest.height);
    else if (m.sceneHash != manifest.sceneHash)
        status.problem =
            fmt::format("it was rendered from another scene ('{}' hashing to {}, the render's {})",
                        m.sceneFile, m.sceneHash, manifest.sceneHash);
    else if (m.seed != manifest.seed || m.sampler != manifest.sampler ||
             m.accelerator != manifest.accelerator)
        status.problem = fmt::format(
            "it was rendered with seed {}, the {} sampler and --accel {}, the render with "
            "seed {}, {} and {}",
            m.seed, m.sampler, m.accelerator, manifest.seed, manifest.sampler, manifest.accelerator);
    else if (window != expected)
        status.problem = fmt::format("it covers the pixels {}, the part {}", describeWindow(window),
                                     describeWindow(expected));
    else if (m.firstSample != part.firstSample || m.endSample > part.endSample)
        status.problem = fmt::format("it holds samples {}, the part [{}, {})", describeRange(m),
                                     part.firstSample, part.endSample);
    else {
        status.state = m.endSample == part.endSample ? PartState::Done : PartState::Partial;
        status.heldEnd = m.endSample;
    }
    return status;
}

std::string describeStatus(const RenderPart& part, const PartStatus& status) {
    switch (status.state) {
        case PartState::Done:
            return "done";
        case PartState::Partial:
            return fmt::format(
                "partial: a checkpoint holds samples [{}, {}) of [{}, {}), written {:.0f} s ago "
                "(running, or stopped and resumable)",
                part.firstSample, status.heldEnd, part.firstSample, part.endSample, status.secondsSinceWrite);
        case PartState::Started:
            return fmt::format("started: its log was written {:.0f} s ago, no checkpoint yet",
                               status.secondsSinceWrite);
        case PartState::Missing:
            return "missing";
        case PartState::Foreign:
            return "not this part's film: " + status.problem;
    }
    return "";
}

void requireAllPartsDone(const PartManifest& manifest, const fs::path& manifestPath) {
    std::string list;
    int notDone = 0;
    for (size_t i = 0; i < manifest.parts.size(); ++i) {
        const RenderPart& part = manifest.parts[i];
        const PartStatus status = partStatus(manifest, part);
        if (status.state == PartState::Done) continue;
        ++notDone;
        list += fmt::format("\n  part {} ({}, {}): {}", i, describePart(part), part.file.string(),
                            describeStatus(part, status));
    }
    if (notDone == 0) return;
    throwFileError(
        manifestPath,
        fmt::format("{} of {} parts are not done; nothing merged:{}\nrender them with: penumbra submit {} "
                    "--resume (the same options as the first submit)",
                    notDone, manifest.parts.size(), list, manifest.scene.string()));
}

}  // namespace penumbra
