// `penumbra submit SCENE --parts N -o OUT.exr ...`: a render split into parts that run as a Slurm
// job array, and the merge jobs that follow it (tools/slurm_batch.h); the manifest
// (tools/part_manifest.h) lists the parts. docs/scale-out.md says how far it goes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tools/slurm_batch.h"

namespace penumbra {

struct SubmitCommand {
    std::string scenePath;
    int parts = 0;
    std::string by = "samples";  // "samples" (ranges of sample indices) or "rows" (bands of rows)
    std::optional<int> spp;
    std::string output;
    bool dryRun = false;  // print the batch scripts; write and submit nothing
    bool resume = false;  // submit only the parts that are not done
    // Passed to every part's render.
    std::optional<std::string> seed;
    std::string resolution, sampler, accel;
    std::optional<uint32_t> passSize;
    int mergeTreeAbove = 16;  // more parts than this: merge in two levels (groups of about sqrt(N))
    SlurmRequest slurm;
};

// Returns the exit status; throws InputError, having submitted nothing, when a check fails.
int runSubmitCommand(const SubmitCommand& command);

}  // namespace penumbra
