#include "tools/submit_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "core/input_limits.h"
#include "film/atomic_file.h"
#include "film/scene_hash.h"
#include "scenes/scene_loader.h"
#include "tools/cli_numbers.h"
#include "tools/part_status.h"
#include "tools/script_text.h"
#include "tools/split_text.h"

namespace fs = std::filesystem;

namespace penumbra {

namespace {

// The program the jobs run: this one, by its absolute path (nodes see the same shared paths).
fs::path thisProgram() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw InputError("cannot find the penumbra program's own path (/proc/self/exe)");
    return self;
}

// The manifest this submit describes, before any job is submitted.
PartManifest plan(const SubmitCommand& cmd, const fs::path& output) {
    PartManifest m;
    m.scene = fs::absolute(cmd.scenePath).lexically_normal();
    m.output = output;
    m.penumbra = thisProgram();
    if (::access(m.penumbra.c_str(), X_OK) != 0)
        throw InputError(fmt::format("the penumbra program {} is not executable", m.penumbra.string()));

    Scene scene = loadScene(m.scene);  // the scene is read (and checked) here, not first on a node
    m.sceneHash = hashSceneFiles(m.scene, scene.meshFiles);
    m.seed = cmd.seed ? std::stoull(*cmd.seed) : scene.settings.seed;  // --seed was checked as digits
    m.sampler = cmd.sampler.empty() ? std::string(samplerKindName(scene.settings.sampler)) : cmd.sampler;
    m.accelerator = cmd.accel.empty() ? "embree" : cmd.accel;
    m.width = scene.film.width;
    m.height = scene.film.height;
    if (cmd.spp && *cmd.spp <= 0)
        throw InputError(fmt::format("--spp: expected a positive integer, got {}", *cmd.spp));
    m.samplesPerPixel = uint32_t(cmd.spp ? *cmd.spp : scene.film.samplesPerPixel);
    if (!cmd.resolution.empty()) {
        const auto wh = splitText(cmd.resolution, 'x');
        if (wh.size() != 2)
            throw InputError(fmt::format("--res: expected WIDTHxHEIGHT, got '{}'", cmd.resolution));
        m.width = int(parseIntegerOption("--res", wh[0], 1, limits::kMaxImageSide));
        m.height = int(parseIntegerOption("--res", wh[1], 1, limits::kMaxImageSide));
        m.renderArguments.insert(m.renderArguments.end(), {"--res", cmd.resolution});
    }
    if (cmd.seed) m.renderArguments.insert(m.renderArguments.end(), {"--seed", *cmd.seed});
    if (!cmd.sampler.empty()) {
        if (cmd.sampler != "stratified" && cmd.sampler != "independent")
            throw InputError(
                fmt::format("--sampler: expected 'stratified' or 'independent', got '{}'", cmd.sampler));
        m.renderArguments.insert(m.renderArguments.end(), {"--sampler", cmd.sampler});
    }
    if (!cmd.accel.empty()) m.renderArguments.insert(m.renderArguments.end(), {"--accel", cmd.accel});
    if (cmd.passSize)
        m.renderArguments.insert(m.renderArguments.end(), {"--pass-size", std::to_string(*cmd.passSize)});

    if (cmd.by != "samples" && cmd.by != "rows")
        throw InputError(fmt::format("--by: expected 'samples' or 'rows', got '{}'", cmd.by));
    m.split = cmd.by == "samples" ? SplitKind::Samples : SplitKind::Rows;
    const fs::path folder = partsFolderFor(output);
    m.parts = splitRender(m.split, cmd.parts, m.samplesPerPixel, m.width, m.height, folder);
    m.groups = mergeGroups(cmd.parts, cmd.mergeTreeAbove, folder);
    return m;
}

// --resume must continue the render the manifest describes, not another.
void checkSameRender(const PartManifest& planned, const PartManifest& stored, const fs::path& manifestPath) {
    auto differ = [&](const char* what, const std::string& now, const std::string& then) {
        throwFileError(manifestPath,
                       fmt::format("--resume: this submit has {} {}, the manifest {}; resubmit with "
                                   "the options of the first submit",
                                   what, now, then));
    };
    if (planned.scene != stored.scene) differ("the scene", planned.scene.string(), stored.scene.string());
    if (planned.sceneHash != stored.sceneHash)
        throwFileError(
            manifestPath,
            fmt::format("--resume: the scene {} (or a mesh it names) has changed since the first submit "
                        "(it hashes to {}, then to {}); its parts cannot be merged with new ones: submit "
                        "it again to another output",
                        planned.scene.string(), planned.sceneHash, stored.sceneHash));
    if (planned.width != stored.width || planned.height != stored.height)
        differ("the resolution", fmt::format("{}x{}", planned.width, planned.height),
               fmt::format("{}x{}", stored.width, stored.height));
    if (planned.samplesPerPixel != stored.samplesPerPixel)
        differ("--spp", std::to_string(planned.samplesPerPixel), std::to_string(stored.samplesPerPixel));
    if (planned.parts.size() != stored.parts.size() || planned.split != stored.split)
        differ("the parts",
               fmt::format("{} by {}", planned.parts.size(),
                           planned.split == SplitKind::Samples ? "samples" : "rows"),
               fmt::format("{} by {}", stored.parts.size(),
                           stored.split == SplitKind::Samples ? "samples" : "rows"));
    if (planned.renderArguments != stored.renderArguments) {
        std::string now, then;
        for (const auto& a : planned.renderArguments) now += " " + a;
        for (const auto& a : stored.renderArguments) then += " " + a;
        differ("the render options", fmt::format("'{}'", now), fmt::format("'{}'", then));
    }
}

void writeScript(const fs::path& path, const std::string& text) {
    writeTextFileAtomically(path, "batch script", text,
                            fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec);
}

std::string jobIdOf(const std::string& recorded) { return recorded.substr(recorded.find(':') + 1); }

}  // namespace

int runSubmitCommand(const SubmitCommand& cmd) {
    requireOneLineOfText("-o", cmd.output);  // before it is named in any message or path
    const fs::path output = fs::absolute(cmd.output).lexically_normal();
    if (output.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", cmd.output));
    // A missing folder is made when the parts folder is (as render -o makes its folder).
    if (fs::is_directory(output.parent_path()) && ::access(output.parent_path().c_str(), W_OK) != 0)
        throw InputError(fmt::format("-o: cannot write in the folder {}", output.parent_path().string()));
    const fs::path manifestPath = manifestPathFor(output);
    const fs::path folder = partsFolderFor(output);

    PartManifest manifest = plan(cmd, output);
    std::vector<int> toRender;
    std::vector<std::string> cancelled;
    if (cmd.resume) {
        if (!fs::exists(manifestPath))
            throw InputError(fmt::format("--resume: there is no manifest {} (submit without --resume first)",
                                         manifestPath.string()));
        PartManifest stored = readManifest(manifestPath);
        checkSameRender(manifest, stored, manifestPath);
        manifest.jobs = stored.jobs;
        manifest.groups = stored.groups;
        // Parts whose task is still queued or running are left to it; merges still waiting on
        // an earlier array are replaced.
        std::vector<std::string> renderJobs, mergeJobs;
        for (const std::string& j : stored.jobs)
            (j.rfind("render:", 0) == 0 ? renderJobs : mergeJobs).push_back(jobIdOf(j));
        if (!cmd.dryRun) {
            std::vector<std::string> all = renderJobs;
            all.insert(all.end(), mergeJobs.begin(), mergeJobs.end());
            for (const QueuedTask& t : queuedTasks(all)) {
                const bool isRender =
                    std::find(renderJobs.begin(), renderJobs.end(), t.jobId) != renderJobs.end();
                if (isRender)
                    throw InputError(
                        fmt::format("--resume: part {} is still in the queue as Slurm job {}_{} ({}); wait "
                                    "for it or scancel it first",
                                    t.taskId, t.jobId, t.taskId, t.state));
                cancelled.push_back(t.jobId);
            }
        }
        for (size_t i = 0; i < manifest.parts.size(); ++i) {
            const PartStatus status = partStatus(manifest, manifest.parts[i]);
            if (status.state == PartState::Foreign)
                throw InputError(
                    fmt::format("--resume: part {}: {} is not this part's film ({}); move it away", i,
                                manifest.parts[i].file.string(), status.problem));
            if (status.state != PartState::Done) toRender.push_back(int(i));
        }
    } else {
        if (fs::exists(manifestPath))
            throw InputError(
                fmt::format("{} exists: this output was submitted before; pass --resume to render its "
                            "missing parts, or remove it and {} to start over",
                            manifestPath.string(), folder.string()));
        for (size_t i = 0; i < manifest.parts.size(); ++i) toRender.push_back(int(i));
    }

    const SlurmRequest& request = cmd.slurm;
    const std::string render =
        toRender.empty() ? "" : renderScript(manifest, manifestPath, request, toRender);
    const std::string groups =
        manifest.groups.empty() ? "" : groupMergeScript(manifest, manifestPath, request);
    const std::string merge = finalMergeScript(manifest, manifestPath, request);
    const fs::path renderPath = folder / "render.sbatch", groupsPath = folder / "merge-groups.sbatch",
                   mergePath = folder / "merge.sbatch";

    if (cmd.dryRun) {
        if (!render.empty()) std::printf("# %s\n%s\n", renderPath.string().c_str(), render.c_str());
        if (!groups.empty())
            std::printf("# %s (sbatch --dependency=afterok:<the render array>)\n%s\n",
                        groupsPath.string().c_str(), groups.c_str());
        std::printf("# %s (sbatch --dependency=afterok:<the %s>)\n%s", mergePath.string().c_str(),
                    groups.empty() ? "render array" : "group merges", merge.c_str());
        std::printf("# dry run: %zu of %zu parts would be submitted; nothing written or submitted\n",
                    toRender.size(), manifest.parts.size());
        return 0;
    }

    if (findOnPath("sbatch").empty())
        throw InputError(
            "sbatch is not on PATH: penumbra submit runs on a Slurm login node (see docs/scale-out.md)");
    std::error_code ec;
    fs::create_directories(folder / "logs", ec);
    if (ec)
        throw InputError(
            fmt::format("{}: cannot create the parts folder: {}", folder.string(), ec.message()));
    writeManifest(manifest, manifestPath);  // first, so the jobs find it
    for (const std::string& id : cancelled) cancelJob(id);
    if (!render.empty()) writeScript(renderPath, render);
    if (!groups.empty()) writeScript(groupsPath, groups);
    writeScript(mergePath, merge);

    std::string after;
    if (!render.empty()) {
        try {
            after = submitBatch(renderPath, "");
        } catch (const InputError& e) {
            // Nothing of this render is queued: a first submit leaves nothing behind, so that it
            // can be run again as it is once the cause is fixed.
            if (!cmd.resume) {
                std::error_code ignored;
                for (const fs::path& written :
                     {manifestPath, renderPath, groupsPath, mergePath, folder / "logs", folder})
                    fs::remove(written, ignored);  // the folders only when empty
            }
            throw;
        }
        manifest.jobs.push_back("render:" + after);
        writeManifest(manifest, manifestPath);
        std::printf("submitted parts %s of %zu as Slurm job array %s\n", arraySpec(toRender).c_str(),
                    manifest.parts.size(), after.c_str());
    } else {
        std::printf("all %zu parts are done; submitting the merge only\n", manifest.parts.size());
    }
    if (!groups.empty()) {
        after = submitBatch(groupsPath, after);
        manifest.jobs.push_back("merge-groups:" + after);
        writeManifest(manifest, manifestPath);
        std::printf("submitted the merge of %zu groups as job array %s\n", manifest.groups.size(),
                    after.c_str());
    }
    after = submitBatch(mergePath, after);
    manifest.jobs.push_back("merge:" + after);
    writeManifest(manifest, manifestPath);
    for (const std::string& id : cancelled) std::printf("cancelled the earlier merge job %s\n", id.c_str());
    std::printf("submitted the merge into %s as job %s\nmanifest: %s\nprogress: penumbra status %s\n",
                output.string().c_str(), after.c_str(), manifestPath.string().c_str(),
                output.string().c_str());
    return 0;
}

}  // namespace penumbra
