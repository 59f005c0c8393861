// The Slurm side of `penumbra submit`: the batch scripts of a split render (a job array that
// renders the parts, merge-group jobs when the merge is a tree, and the final merge) and the
// commands that submit and inspect them (sbatch, squeue, scancel, found on PATH). Every value a
// script holds is checked to be one line of text and quoted for what reads it (tools/script_text.h);
// the commands run without a shell (tools/run_program.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tools/part_manifest.h"

namespace penumbra {

// What every job of the render asks of Slurm.
struct SlurmRequest {
    std::string partition;  // empty: the cluster's default
    std::string time;       // a time limit, as sbatch takes it; empty: the partition's
    int cpusPerTask = 0;    // 0: a whole node per part (--exclusive)
    double checkpointMinutes = 10;
    std::vector<std::string> sbatchArguments;  // more #SBATCH lines (--account=..., --qos=...)
};

// "0-7" or "3,5": the array indices of the parts.
std::string arraySpec(const std::vector<int>& indices);

// Each script is returned whole or not at all: InputError when a value cannot be written safely.

// The job array that renders parts `indices`: task i renders part i to its file with
// --checkpoint, continuing the part's own checkpoint when there is one (a requeued, preempted
// or resubmitted task).
std::string renderScript(const PartManifest& manifest, const std::filesystem::path& manifestPath,
                         const SlurmRequest& request, const std::vector<int>& indices);
// The job array that merges each merge group into its file (task g: group g).
std::string groupMergeScript(const PartManifest& manifest, const std::filesystem::path& manifestPath,
                             const SlurmRequest& request);
// The job that merges everything into the manifest's output.
std::string finalMergeScript(const PartManifest& manifest, const std::filesystem::path& manifestPath,
                             const SlurmRequest& request);

// Runs `sbatch --parsable [--dependency=afterok:AFTER] SCRIPT`; returns the job id. Throws
// InputError with sbatch's message when it fails.
std::string submitBatch(const std::filesystem::path& script, const std::string& afterJob);

// Where a program is on PATH; empty when it is not.
std::string findOnPath(const std::string& program);

// The tasks of `jobIds` still in the queue (pending, running, ...), as squeue reports them:
// job id, array task id ("" when not an array task) and state. Throws InputError when squeue fails.
struct QueuedTask {
    std::string jobId, taskId, state;
};
std::vector<QueuedTask> queuedTasks(const std::vector<std::string>& jobIds);

// scancel JOBID; throws InputError when it fails.
void cancelJob(const std::string& jobId);

}  // namespace penumbra
