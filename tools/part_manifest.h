// The manifest of a render split into parts for a cluster (`penumbra submit`): the scene, the
// output, and each part's film file with the samples (or pixel rows) it renders, written as
// OUT.parts.json beside OUT.exr. `merge --manifest`, `status` and `submit --resume` work from it
// and the part files alone, without asking the scheduler.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "film/film.h"

namespace penumbra {

// One part: samples [firstSample, endSample) of the pixels in `crop` (none: every pixel).
struct RenderPart {
    std::filesystem::path file;
    uint32_t firstSample = 0, endSample = 0;
    std::optional<PixelWindow> crop;
};

// Parts merged together first when a merge runs as a tree (docs/scale-out.md): parts
// [firstPart, endPart) go into `file`.
struct MergeGroup {
    std::filesystem::path file;
    int firstPart = 0, endPart = 0;
};

enum class SplitKind { Samples, Rows };

struct PartManifest {
    std::filesystem::path scene;     // absolute
    std::filesystem::path output;    // the merged EXR, absolute
    std::filesystem::path penumbra;  // the program the jobs run, absolute
    // What decides every sample, which each part's film must record: hashSceneFiles() of the
    // scene and its meshes, the seed, the sampler and the traversal backend.
    std::string sceneHash;
    uint64_t seed = 0;
    std::string sampler, accelerator;
    int width = 0, height = 0;
    uint32_t samplesPerPixel = 0;
    SplitKind split = SplitKind::Samples;
    std::vector<std::string> renderArguments;  // passed to every part's render (--seed, --res, ...)
    std::vector<RenderPart> parts;
    std::vector<MergeGroup> groups;  // empty: one merge of every part
    std::vector<std::string> jobs;   // the Slurm jobs submitted for it, latest last
};

// OUT.parts.json and the folder OUT.parts/ (part films, batch scripts, logs) of OUT.exr.
std::filesystem::path manifestPathFor(const std::filesystem::path& output);
std::filesystem::path partsFolderFor(const std::filesystem::path& output);
// OUT.exr (absolute) of OUT.parts.json; throws InputError when the name is not of that form.
std::filesystem::path outputForManifest(const std::filesystem::path& manifestPath);

// Splits samples [0, spp) into `count` contiguous ranges, or the image into `count` bands of
// whole rows (every sample), as even as integers allow; files part-0000.exr, ... in `folder`.
// Throws InputError when there are more parts than samples (or rows).
std::vector<RenderPart> splitRender(SplitKind split, int count, uint32_t spp, int width, int height,
                                    const std::filesystem::path& folder);

// Groups of about sqrt(N) consecutive parts when there are more than `treeAbove` parts (a
// two-level merge), none otherwise; files group-000.exr, ... in `folder`.
std::vector<MergeGroup> mergeGroups(int partCount, int treeAbove, const std::filesystem::path& folder);

// "samples [8, 16)" or "rows [0, 45)": what a part renders, for messages.
std::string describePart(const RenderPart& part);
// The samples and window a film of parts [firstPart, endPart) holds once merged.
RenderPart unionOfParts(const PartManifest& manifest, int firstPart, int endPart);

// Written atomically; throws InputError naming the path when it cannot be.
void writeManifest(const PartManifest& manifest, const std::filesystem::path& path);
// Throws InputError "FILE: /json/pointer: ..." when it is not a manifest written by submit,
// including when it names its output, a part or a group otherwise than submit names them beside it.
PartManifest readManifest(const std::filesystem::path& path);

}  // namespace penumbra
