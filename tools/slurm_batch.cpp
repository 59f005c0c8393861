#include "tools/slurm_batch.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <set>

#include "core/error.h"
#include "tools/part_status.h"
#include "tools/run_program.h"
#include "tools/script_text.h"
#include "tools/split_text.h"

namespace fs = std::filesystem;

namespace penumbra {

namespace {

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
}

// A path written into a script, checked to be one line of text.
std::string checkedPath(const char* what, const fs::path& path) {
    requireOneLineOfText(what, path.string());
    return path.string();
}

// The #SBATCH lines every job of the render shares, each value one argument as sbatch reads it.
std::string commonDirectives(const SlurmRequest& request) {
    std::string lines;
    if (!request.partition.empty()) {
        requireOneLineOfText("--partition", request.partition);
        lines += fmt::format("#SBATCH --partition={}\n", sbatchQuote(request.partition));
    }
    if (!request.time.empty()) {
        requireOneLineOfText("--time", request.time);
        lines += fmt::format("#SBATCH --time={}\n", sbatchQuote(request.time));
    }
    for (const std::string& argument : request.sbatchArguments) {
        requireOneLineOfText("--sbatch", argument);
        lines += fmt::format("#SBATCH {}\n", sbatchQuote(argument));
    }
    return lines;
}

// "#SBATCH --output=FOLDER/NAME": the job's log in the parts' log folder.
std::string logDirective(const PartManifest& m, const std::string& namePattern) {
    const fs::path folder = partLogPath(m.parts.front()).parent_path();
    return fmt::format("#SBATCH --output={}\n",
                       sbatchQuoteFilenamePattern(checkedPath("the log folder", folder) + "/", namePattern));
}

// The first line of each script says what it is for; the output's name is written quoted.
std::string describedOutput(const PartManifest& m) { return shellQuote(checkedPath("-o", m.output)); }

}  // namespace

std::string arraySpec(const std::vector<int>& indices) {
    std::string spec;
    for (size_t i = 0; i < indices.size();) {
        size_t j = i;
        while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
        if (!spec.empty()) spec += ",";
        spec += j > i ? fmt::format("{}-{}", indices[i], indices[j]) : std::to_string(indices[i]);
        i = j + 1;
    }
    return spec;
}

std::string renderScript(const PartManifest& m, const fs::path& manifestPath, const SlurmRequest& request,
                         const std::vector<int>& indices) {
    std::string s = "#!/bin/bash\n";
    s += fmt::format("# penumbra submit: the parts of {} ({} in all, listed in {}), one array task each.\n",
                     describedOutput(m), m.parts.size(),
                     shellQuote(checkedPath("the manifest", manifestPath)));
    s += "#SBATCH --job-name=penumbra-parts\n";
    s += fmt::format("#SBATCH --array={}\n", arraySpec(indices));
    s += logDirective(m, "part-%4a.log");
    s += "#SBATCH --open-mode=append\n";
    // Preemption and node failures put the task back in the queue; it resumes its checkpoint.
    s += "#SBATCH --requeue\n";
    s += request.cpusPerTask > 0 ? fmt::format("#SBATCH --cpus-per-task={}\n", request.cpusPerTask)
                                 : std::string("#SBATCH --exclusive\n");
    // Before the time limit the render gets SIGTERM, writes its checkpoint and stops.
    if (!request.time.empty()) s += "#SBATCH --signal=B:TERM@120\n";
    s += commonDirectives(request);
    s += "set -euo pipefail\n";
    s += "case \"${SLURM_ARRAY_TASK_ID:?penumbra: run this script as a Slurm array task}\" in\n";
    for (int i : indices) {
        const RenderPart& p = m.parts[size_t(i)];
        const std::string range =
            p.crop ? fmt::format("--crop {},{},{},{}", p.crop->x0, p.crop->x1, p.crop->y0, p.crop->y1)
                   : fmt::format("--samples {}:{}", p.firstSample, p.endSample);
        s += fmt::format("    {}) part={}; range=({}) ;;\n", i,
                         shellQuote(checkedPath("a part's file", p.file)), range);
    }
    s += "    *) echo \"penumbra: error: this render has no part ${SLURM_ARRAY_TASK_ID}\" >&2; exit 2 ;;\n";
    s += "esac\n";
    s += "# A requeued, preempted or resubmitted task continues its own checkpoint.\n";
    s += "resume=()\n";
    s += "if [ -e \"$part\" ]; then resume=(--resume \"$part\"); fi\n";
    s += "echo \"penumbra: part ${SLURM_ARRAY_TASK_ID} (job ${SLURM_JOB_ID}) on $(hostname) at $(date -u "
         "+%FT%TZ), "
         "restart ${SLURM_RESTART_COUNT:-0}${resume[*]:+, continuing $part}\"\n";
    std::string arguments;
    for (const std::string& a : m.renderArguments) {
        requireOneLineOfText("a render option", a);
        arguments += fmt::format(" {}", shellQuote(a));
    }
    s += fmt::format(
        "exec {} render {} --spp {} \"${{range[@]}}\" -o \"$part\" --no-display --checkpoint {} "
        "--threads \"${{SLURM_CPUS_PER_TASK:-0}}\"{} \"${{resume[@]}}\"\n",
        shellQuote(checkedPath("the penumbra program", m.penumbra)),
        shellQuote(checkedPath("the scene", m.scene)), m.samplesPerPixel, request.checkpointMinutes,
        arguments);
    return s;
}

std::string groupMergeScript(const PartManifest& m, const fs::path& manifestPath,
                             const SlurmRequest& request) {
    std::string s = "#!/bin/bash\n";
    s += fmt::format(
        "# penumbra submit: the first level of the merge of {}: group g of parts into its file.\n",
        describedOutput(m));
    s += "#SBATCH --job-name=penumbra-merge-groups\n";
    s += fmt::format("#SBATCH --array=0-{}\n", m.groups.size() - 1);
    s += logDirective(m, "group-%3a.log");
    s += "#SBATCH --open-mode=append\n";
    s += commonDirectives(request);
    s += fmt::format("exec {} merge --manifest {} --group \"${{SLURM_ARRAY_TASK_ID}}\"\n",
                     shellQuote(checkedPath("the penumbra program", m.penumbra)),
                     shellQuote(checkedPath("the manifest", manifestPath)));
    return s;
}

std::string finalMergeScript(const PartManifest& m, const fs::path& manifestPath,
                             const SlurmRequest& request) {
    std::string s = "#!/bin/bash\n";
    s += fmt::format("# penumbra submit: merges the parts of {} (checked done) into it.\n",
                     describedOutput(m));
    s += "#SBATCH --job-name=penumbra-merge\n";
    s += logDirective(m, "merge.log");
    s += "#SBATCH --open-mode=append\n";
    s += commonDirectives(request);
    s += fmt::format("exec {} merge --manifest {}\n",
                     shellQuote(checkedPath("the penumbra program", m.penumbra)),
                     shellQuote(checkedPath("the manifest", manifestPath)));
    return s;
}

std::string submitBatch(const fs::path& script, const std::string& afterJob) {
    std::vector<std::string> command = {"sbatch", "--parsable"};
    if (!afterJob.empty()) command.push_back("--dependency=afterok:" + afterJob);
    command.push_back(script.string());
    const ProgramResult r = runProgram(command);
    const std::string out = trimmed(r.output);
    // --parsable prints "JOBID" or "JOBID;CLUSTER".
    const std::string id = out.substr(0, out.find(';'));
    if (r.exitStatus != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(
            fmt::format("{} failed (exit status {}): {}", commandLineFor(command), r.exitStatus, out));
    return id;
}

std::string findOnPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    for (const std::string& dir : splitText(path ? path : "", ':')) {
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return "";
}

std::vector<QueuedTask> queuedTasks(const std::vector<std::string>& jobIds) {
    std::vector<QueuedTask> tasks;
    if (jobIds.empty()) return tasks;
    // Every job of this user, filtered here: squeue -j fails on ids the controller has forgotten.
    const ProgramResult r = runProgram({"squeue", "--me", "--noheader", "--array", "--format=%F %K %T"});
    if (r.exitStatus != 0)
        throw InputError(fmt::format("squeue failed (exit status {}): {}", r.exitStatus, trimmed(r.output)));
    const std::set<std::string> wanted(jobIds.begin(), jobIds.end());
    for (const std::string& line : splitText(r.output, '\n')) {
        const std::vector<std::string> fields = splitText(line, ' ');
        if (fields.size() != 3 || !wanted.count(fields[0])) continue;
        tasks.push_back(QueuedTask{fields[0], fields[1] == "N/A" ? "" : fields[1], fields[2]});
    }
    return tasks;
}

void cancelJob(const std::string& jobId) {
    const ProgramResult r = runProgram({"scancel", jobId});
    if (r.exitStatus != 0) throw InputError(fmt::format("scancel {} failed: {}", jobId, trimmed(r.output)));
}

}  // namespace penumbra
