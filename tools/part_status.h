// How far each part of a split render has come, from its film file and its log alone (no
// scheduler state): `penumbra status`, `merge --manifest` and `submit --resume` ask this.
#pragma once

#include <filesystem>
#include <string>

#include "tools/part_manifest.h"

namespace penumbra {

enum class PartState {
    Done,     // the part's film holds all its samples
    Partial,  // a checkpoint holds the first of its samples: running, or stopped and resumable
    Started,  // no film yet, but its job has written its log: running before its first checkpoint
    Missing,  // neither film nor log
    Foreign,  // a file is there that is not this part's film (another render, or unreadable)
};

struct PartStatus {
    PartState state = PartState::Missing;
    uint32_t heldEnd = 0;          // Partial: the film holds samples [part.firstSample, heldEnd)
    double secondsSinceWrite = 0;  // Done, Partial, Started: since the film (or log) was last written
    std::string problem;           // Foreign: why
};

// OUT.parts/logs/part-0003.log: where the batch script's output goes.
std::filesystem::path partLogPath(const RenderPart& part);

// Reads only the film's headers (cheap for any size of part).
PartStatus partStatus(const PartManifest& manifest, const RenderPart& part);

// Throws InputError naming the manifest and, for each part that is not done, its number, range,
// file and state; does nothing when every part is done.
void requireAllPartsDone(const PartManifest& manifest, const std::filesystem::path& manifestPath);

// "done", "partial: holds samples [0, 4) of [0, 8)", "missing", ...
std::string describeStatus(const RenderPart& part, const PartStatus& status);

}  // namespace penumbra
