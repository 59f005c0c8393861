#include "tools/part_manifest.h"

#include <fmt/format.h>

#include <cmath>

#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "film/atomic_file.h"
#include "scenes/json_reader.h"

namespace fs = std::filesystem;

namespace penumbra {

namespace {

constexpr const char* kKind = "penumbra render parts";
constexpr int kVersion = 1;
constexpr uint64_t kMaxManifestBytes = uint64_t(256) << 20;

const char* splitName(SplitKind split) { return split == SplitKind::Samples ? "samples" : "rows"; }

std::string partFileName(size_t index) { return fmt::format("part-{:04}.exr", index); }
std::string groupFileName(size_t index) { return fmt::format("group-{:03}.exr", index); }

// Whether `path` is `expected`: the same name in the same folder (reached by the same path, or
// another one to the same folder).
bool isSameFile(const fs::path& path, const fs::path& expected) {
    if (path.filename() != expected.filename()) return false;
    const fs::path folder = fs::absolute(path).lexically_normal().parent_path(),
                   expectedFolder = fs::absolute(expected).lexically_normal().parent_path();
    std::error_code ec;
    return folder == expectedFolder || fs::equivalent(folder, expectedFolder, ec);
}

// A manifest names its output, parts and merge groups only as submit names them, beside the
// manifest: `merge --manifest` and the jobs write these files, so a crafted manifest must not choose
// them (it could otherwise overwrite any file its reader can write).
void requireNamedBySubmit(const JsonValue& value, const fs::path& path, const fs::path& expected) {
    if (!isSameFile(path, expected))
        value.fail(fmt::format("expected {} (submit names it after the manifest, beside it), found {}",
                               expected.string(), path.string()));
}

// The even split of [0, total) into `count` ranges: range i is [i * total / count, (i+1) * total / count).
uint32_t cut(uint64_t total, int count, int i) { return uint32_t(total * uint64_t(i) / uint64_t(count)); }

}  // namespace

fs::path manifestPathFor(const fs::path& output) { return fs::path(output).replace_extension(".parts.json"); }
fs::path partsFolderFor(const fs::path& output) { return fs::path(output).replace_extension(".parts"); }

fs::path outputForManifest(const fs::path& manifestPath) {
    const std::string name = manifestPath.filename().string(), suffix = ".parts.json";
    if (name.size() <= suffix.size() || !name.ends_with(suffix))
        throwFileError(manifestPath, "a manifest is named OUT.parts.json after its output OUT.exr");
    return fs::absolute(manifestPath)
        .lexically_normal()
        .replace_filename(name.substr(0, name.size() - suffix.size()) + ".exr");
}

std::vector<RenderPart> splitRender(SplitKind split, int count, uint32_t spp, int width, int height,
                                    const fs::path& folder) {
    const uint64_t total = split == SplitKind::Samples ? spp : uint64_t(height);
    if (count < 1 || uint64_t(count) > total)
        throw InputError(fmt::format("--parts: {} parts of {} {} leave some part empty (at most {})", count,
                                     total, split == SplitKind::Samples ? "samples per pixel" : "rows",
                                     total));
    std::vector<RenderPart> parts;
    for (int i = 0; i < count; ++i) {
        RenderPart part;
        part.file = folder / partFileName(size_t(i));
        if (split == SplitKind::Samples) {
            part.firstSample = cut(total, count, i);
            part.endSample = cut(total, count, i + 1);
        } else {
            part.endSample = spp;
            part.crop = PixelWindow{0, width, int(cut(total, count, i)), int(cut(total, count, i + 1))};
        }
        parts.push_back(part);
    }
    return parts;
}

std::vector<MergeGroup> mergeGroups(int partCount, int treeAbove, const fs::path& folder) {
    if (partCount <= treeAbove) return {};
    const int size = int(std::ceil(std::sqrt(double(partCount))));
    std::vector<MergeGroup> groups;
    for (int first = 0; first < partCount; first += size)
        groups.push_back(
            MergeGroup{folder / groupFileName(groups.size()), first, std::min(partCount, first + size)});
    return groups;
}

std::string describePart(const RenderPart& part) {
    if (part.crop) return fmt::format("rows [{}, {})", part.crop->y0, part.crop->y1);
    return fmt::format("samples [{}, {})", part.firstSample, part.endSample);
}

RenderPart unionOfParts(const PartManifest& manifest, int firstPart, int endPart) {
    const RenderPart &first = manifest.parts[size_t(firstPart)], &last = manifest.parts[size_t(endPart - 1)];
    RenderPart u;
    u.firstSample = first.firstSample;
    u.endSample = last.endSample;
    if (first.crop) {
        u.crop = PixelWindow{0, manifest.width, first.crop->y0, last.crop->y1};
        if (*u.crop == PixelWindow{0, manifest.width, 0, manifest.height}) u.crop.reset();
    }
    return u;
}

void writeManifest(const PartManifest& m, const fs::path& path) {
    nlohmann::ordered_json j;
    j["manifest"] = kKind;
    j["version"] = kVersion;
    j["scene"] = m.scene.string();
    j["output"] = m.output.string();
    j["penumbra"] = m.penumbra.string();
    j["scene_hash"] = m.sceneHash;
    j["seed"] = std::to_string(m.seed);  // a string: JSON readers lose integers beyond 2^53
    j["sampler"] = m.sampler;
    j["accel"] = m.accelerator;
    j["resolution"] = {m.width, m.height};
    j["spp"] = m.samplesPerPixel;
    j["split"] = splitName(m.split);
    j["render_arguments"] = m.renderArguments;
    j["parts"] = nlohmann::ordered_json::array();
    for (const RenderPart& p : m.parts) {
        nlohmann::ordered_json part;
        part["file"] = p.file.string();
        part["samples"] = {p.firstSample, p.endSample};
        if (p.crop) part["crop"] = {p.crop->x0, p.crop->x1, p.crop->y0, p.crop->y1};
        j["parts"].push_back(part);
    }
    j["merge_groups"] = nlohmann::ordered_json::array();
    for (const MergeGroup& g : m.groups)
        j["merge_groups"].push_back({{"file", g.file.string()}, {"parts", {g.firstPart, g.endPart}}});
    j["jobs"] = m.jobs;
    const std::string text = j.dump(2) + "\n";
    writeTextFileAtomically(path, "manifest", text);
}

PartManifest readManifest(const fs::path& path) {
    const std::string text = InputFile(path, "manifest", kMaxManifestBytes).readAll();
    const Json json = parseJsonText(text, path.string());
    const fs::path output = outputForManifest(path), folder = partsFolderFor(output);
    const JsonValue root(json, path.string(), "");
    const JsonObject top(
        root, {"manifest", "version", "scene", "output", "penumbra", "scene_hash", "seed", "sampler", "accel",
               "resolution", "spp", "split", "render_arguments", "parts", "merge_groups", "jobs"});
    if (top.require("manifest").string() != kKind)
        top.require("manifest")
            .fail(fmt::format("expected \"{}\": this is not a manifest written by penumbra submit", kKind));
    top.require("version").integer(kVersion, kVersion);

    PartManifest m;
    m.scene = top.require("scene").string();
    m.output = top.require("output").string();
    requireNamedBySubmit(top.require("output"), m.output, output);
    m.penumbra = top.require("penumbra").string();
    m.sceneHash = top.require("scene_hash").string();
    const JsonValue seed = top.require("seed");
    const std::string seedText = seed.string();
    if (seedText.empty() || seedText.size() > 20 ||
        seedText.find_first_not_of("0123456789") != std::string::npos)
        seed.failExpected("a seed as a string of decimal digits");
    try {
        m.seed = std::stoull(seedText);
    } catch (const std::exception&) {
        seed.failExpected("a seed below 2^64");
    }
    m.sampler = top.require("sampler").string();
    m.accelerator = top.require("accel").string();
    const JsonValue resolution = top.require("resolution");
    if (resolution.arraySize() != 2) resolution.failExpected("[width, height]");
    m.width = int(resolution.element(0).integer(1, limits::kMaxImageSide));
    m.height = int(resolution.element(1).integer(1, limits::kMaxImageSide));
    m.samplesPerPixel = uint32_t(top.require("spp").integer(1, int64_t(1) << 30));
    m.split = top.require("split").choice({"samples", "rows"}) == 0 ? SplitKind::Samples : SplitKind::Rows;
    for (const JsonValue& a : top.require("render_arguments").elements())
        m.renderArguments.push_back(a.string());

    for (const JsonValue& value : top.require("parts").elements()) {
        const JsonObject p(value, {"file", "samples", "crop"});
        RenderPart part;
        part.file = p.require("file").string();
        requireNamedBySubmit(p.require("file"), part.file, folder / partFileName(m.parts.size()));
        const JsonValue samples = p.require("samples");
        if (samples.arraySize() != 2) samples.failExpected("[first, end]");
        part.firstSample = uint32_t(samples.element(0).integer(0, m.samplesPerPixel - 1));
        part.endSample = uint32_t(samples.element(1).integer(part.firstSample + 1, m.samplesPerPixel));
        if (const auto crop = p.get("crop")) {
            if (crop->arraySize() != 4) crop->failExpected("[x0, x1, y0, y1]");
            const PixelWindow w{
                int(crop->element(0).integer(0, m.width - 1)), int(crop->element(1).integer(1, m.width)),
                int(crop->element(2).integer(0, m.height - 1)), int(crop->element(3).integer(1, m.height))};
            if (w.x1 <= w.x0 || w.y1 <= w.y0) crop->fail("expected x0 < x1 and y0 < y1");
            part.crop = w;
        }
        m.parts.push_back(part);
    }
    if (m.parts.empty()) top.require("parts").failExpected("at least one part");

    for (const JsonValue& value : top.require("merge_groups").elements()) {
        const JsonObject g(value, {"file", "parts"});
        MergeGroup group;
        group.file = g.require("file").string();
        requireNamedBySubmit(g.require("file"), group.file, folder / groupFileName(m.groups.size()));
        const JsonValue range = g.require("parts");
        if (range.arraySize() != 2) range.failExpected("[first part, end part]");
        group.firstPart = int(range.element(0).integer(0, int64_t(m.parts.size()) - 1));
        group.endPart = int(range.element(1).integer(group.firstPart + 1, int64_t(m.parts.size())));
        m.groups.push_back(group);
    }
    for (const JsonValue& job : top.require("jobs").elements()) m.jobs.push_back(job.string());
    return m;
}

}  // namespace penumbra
