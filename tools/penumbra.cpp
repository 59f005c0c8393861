// penumbra: the command-line program.
//
//   penumbra render SCENE [--spp N] [--seed S] [--threads N] [--res WxH] [--accel embree|bvh]
//                   [--adaptive T [--min-spp N] [--adaptive-error relative|absolute]] [-o PATH] ...
//   penumbra crosscheck SCENE [--rays N] [--seed S] [--json]
//   penumbra merge PART.exr... -o OUT.exr    (or --manifest OUT.parts.json)
//   penumbra submit SCENE --parts N --spp S -o OUT.exr [--by samples|rows] [--dry-run] [--resume] ...
//   penumbra status OUT.exr
//   penumbra converge SCENE --spp 1,2,4,...,1024 [--sampler ...] [--reference REF.exr] -o DIR
//   penumbra convert SCENE.pbrt -o SCENE.json
//
// SCENE is penumbra's JSON (scenes/README.md) or a pbrt-v4 scene (.pbrt, docs/pbrt-import.md).
//
// Bad input is reported as "penumbra: error: FILE:LINE: message" (or a JSON pointer instead of
// the line) with a non-zero exit status, and no output file is written.

#include <fmt/core.h>
#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/input_limits.h"
#include "film/atomic_file.h"
#include "film/display_image.h"
#include "film/film.h"
#include "film/film_exr.h"
#include "formats/scene_file.h"
#include "renderer/render.h"
#include "renderer/render_job.h"
#include "textures/texture_plugin_loader.h"
#include "tools/adaptive_options.h"
#include "tools/cli_numbers.h"
#include "tools/converge.h"
#include "tools/crosscheck.h"
#include "tools/help_formatter.h"
#include "tools/merge_command.h"
#include "tools/render_report.h"
#include "tools/split_text.h"
#include "tools/status_command.h"
#include "tools/submit_command.h"

namespace fs = std::filesystem;
using namespace penumbra;

namespace {

constexpr const char* kVersion = PENUMBRA_VERSION;

struct RenderCommand {
    std::string scenePath;
    std::optional<int> spp;
    std::optional<uint64_t> seed;
    int threads = 0;
    std::string resolution;  // "WxH"
    std::string sampler;
    std::string crop;     // "x0,x1,y0,y1"
    std::string samples;  // "a:b"
    std::string output;
    bool noDisplay = false;
    bool quiet = false;
    bool textureStats = false;
    std::string accel = "embree";
    std::string film = "full";                 // full: resumable and mergeable; beauty: image and AOVs only
    std::string view;                          // OpenColorIO view of the display image
    float exposure = 0.0f;                     // stops, applied before the view
    std::string resume;                        // a film to continue up to --spp
    std::optional<double> checkpointMinutes;   // write the film every so often (0: after every pass)
    std::optional<uint32_t> passSize;          // sample indices per pass
    std::string patch;                         // a JSON merge patch applied to the scene
    std::optional<double> adaptiveThreshold;   // --adaptive
    std::optional<int64_t> minSpp;             // --min-spp
    std::optional<std::string> adaptiveError;  // --adaptive-error
};

// SIGINT / SIGTERM ask the render to stop at the end of the current pass; the film as of that
// pass is written and penumbra exits with 128 + the signal's number. A second signal kills.
std::atomic<bool> gStopRequested{false};
volatile std::sig_atomic_t gStopSignal = 0;

extern "C" void onStopSignal(int signal) {
    gStopSignal = signal;
    gStopRequested.store(true);
}

void installStopHandlers() {
    struct sigaction action {};
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND | SA_RESTART;  // the second signal gets the default action
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

// --seed: checked as text before CLI11 converts it (which wraps "-1" and saturates 2^64).
const CLI::Validator kSeedText([](std::string& text) { return checkSeedText(text); }, "SEED");

// --checkpoint: a finite number of minutes >= 0 ("nan" and "inf" are numbers to CLI11).
const CLI::Validator kCheckpointMinutes(
    [](std::string& text) -> std::string {
        try {
            size_t used = 0;
            const double minutes = std::stod(text, &used);
            if (used == text.size() && std::isfinite(minutes) && minutes >= 0) return "";
        } catch (const std::exception&) {
        }
        return fmt::format("expected a finite number of minutes >= 0, got '{}'", text);
    },
    "MINUTES");

// Command-line integers: 1 to 2^30 (a positive count or size), or 0 to 2^30 (an index or a pixel).
int parsePositive(const std::string& option, const std::string& text) {
    return int(parseIntegerOption(option, text, 1, int64_t(1) << 30));
}
int parseNonNegative(const std::string& option, const std::string& text) {
    return int(parseIntegerOption(option, text, 0, int64_t(1) << 30));
}

// The options that decide which samples a film holds, as given: a continuation must repeat them.
std::string filmDefiningOptions(const RenderCommand& cmd) {
    std::string text;
    auto add = [&](const char* option, const std::string& value) {
        if (!value.empty()) text += fmt::format(" {} {}", option, shellWord(value));
    };
    if (cmd.seed) add("--seed", std::to_string(*cmd.seed));
    add("--res", cmd.resolution);
    add("--sampler", cmd.sampler);
    add("--crop", cmd.crop);
    if (cmd.accel != "embree") add("--accel", cmd.accel);
    if (cmd.adaptiveThreshold) add("--adaptive", fmt::format("{}", *cmd.adaptiveThreshold));
    if (cmd.minSpp) add("--min-spp", std::to_string(*cmd.minSpp));
    if (cmd.adaptiveError) add("--adaptive-error", *cmd.adaptiveError);
    return text;
}

int runRender(const RenderCommand& cmd) {
    SceneFileOptions sceneOptions;
    sceneOptions.patch = cmd.patch;
    Scene scene = loadSceneFile(cmd.scenePath, sceneOptions);
    if (cmd.spp) {
        if (*cmd.spp <= 0)
            throw InputError(fmt::format("--spp: expected a positive integer, got {}", *cmd.spp));
        scene.film.samplesPerPixel = *cmd.spp;
    }
    if (cmd.seed) scene.settings.seed = *cmd.seed;
    if (!cmd.sampler.empty()) {
        if (cmd.sampler == "stratified")
            scene.settings.sampler = SamplerKind::Stratified;
        else if (cmd.sampler == "independent")
            scene.settings.sampler = SamplerKind::Independent;
        else
            throw InputError(
                fmt::format("--sampler: expected 'stratified' or 'independent', got '{}'", cmd.sampler));
    }
    if (!cmd.resolution.empty()) {
        const auto parts = splitText(cmd.resolution, 'x');
        if (parts.size() != 2)
            throw InputError(fmt::format("--res: expected WIDTHxHEIGHT, got '{}'", cmd.resolution));
        // The scene's own limit (film.resolution), not 2^30.
        scene.film.width = int(parseIntegerOption("--res", parts[0], 1, limits::kMaxImageSide));
        scene.film.height = int(parseIntegerOption("--res", parts[1], 1, limits::kMaxImageSide));
    }
    applyAdaptiveOptions(scene, cmd.adaptiveThreshold, cmd.minSpp, cmd.adaptiveError);

    RenderOptions options;
    options.threads = cmd.threads;
    options.accelerator = cmd.accel == "bvh" ? AcceleratorKind::Bvh : AcceleratorKind::Embree;
    options.endSample = uint32_t(scene.film.samplesPerPixel);
    if (!cmd.samples.empty()) {
        const auto parts = splitText(cmd.samples, ':');
        if (parts.size() != 2)
            throw InputError(fmt::format("--samples: expected FIRST:END, got '{}'", cmd.samples));
        options.firstSample = uint32_t(parseNonNegative("--samples", parts[0]));
        options.endSample = uint32_t(parsePositive("--samples", parts[1]));
        if (options.firstSample >= options.endSample)
            throw InputError(fmt::format("--samples: FIRST must be below END, got '{}'", cmd.samples));
        if (scene.film.adaptive && options.firstSample > 0)
            throw InputError(
                "--samples: an adaptive render (--adaptive, film.adaptive) starts at sample 0, where its "
                "pixels' decisions start; use --checkpoint and --resume to split it in time");
    }
    if (!cmd.crop.empty()) {
        const auto parts = splitText(cmd.crop, ',');
        if (parts.size() != 4)
            throw InputError(fmt::format("--crop: expected x0,x1,y0,y1, got '{}'", cmd.crop));
        options.crop =
            PixelWindow{parseNonNegative("--crop", parts[0]), parseNonNegative("--crop", parts[1]),
                        parseNonNegative("--crop", parts[2]), parseNonNegative("--crop", parts[3])};
    } else if (scene.film.cropWindow) {
        options.crop = cropWindowPixels(*scene.film.cropWindow, scene.film.width, scene.film.height);
    }

    fs::path exrPath = cmd.output.empty()
                           ? fs::path("out") / (fs::path(cmd.scenePath).stem().string() + ".exr")
                           : fs::path(cmd.output);
    if (exrPath.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", exrPath.string()));
    const fs::path displayPath = fs::path(exrPath).replace_extension(".png");

    const FilmContents contents = cmd.film == "beauty" ? FilmContents::Beauty : FilmContents::Full;
    if (contents == FilmContents::Beauty) {
        const char* needsFull = !cmd.samples.empty()    ? "--samples (a part to merge)"
                                : cmd.checkpointMinutes ? "--checkpoint"
                                : !cmd.resume.empty()   ? "--resume"
                                                        : nullptr;
        if (needsFull)
            throw InputError(
                fmt::format("--film beauty: {} needs the film's sums, which only --film full (the default) "
                            "writes",
                            needsFull));
    }
    DisplayOptions display;
    display.view = cmd.view;
    display.exposure = cmd.exposure;
    if (!cmd.noDisplay) checkDisplayOptions(display);  // before the render, not after it

    const bool interactive = !cmd.quiet && isatty(STDERR_FILENO);
    ProgressLine progress(interactive);
    options.progress = [&](size_t done, size_t total) { progress.update(done, total); };

    // Passes: about a million samples each unless --pass-size says otherwise (defaultPassSize).
    const PixelWindow window = options.crop.value_or(PixelWindow{0, scene.film.width, 0, scene.film.height});
    const uint64_t windowPixels =
        uint64_t(std::max(1, window.width())) * uint64_t(std::max(1, window.height()));
    options.passSize = cmd.passSize ? *cmd.passSize : defaultPassSize(windowPixels);
    if (options.passSize == 0) throw InputError("--pass-size: expected a positive integer");
    options.cancel = &gStopRequested;

    RenderJob job(scene, SceneSource::of(cmd.scenePath, scene), options);
    // --resume: continue the film in the file from where it ends up to --spp, or to END of
    // --samples FIRST:END when the film starts at FIRST (the same samples, so the result is the
    // same bit for bit as one render).
    if (!cmd.resume.empty())
        job.resumeFrom(cmd.resume, cmd.samples.empty() ? std::nullopt : std::optional(options.firstSample));
    if (cmd.checkpointMinutes)
        job.checkpointEvery(*cmd.checkpointMinutes, exrPath, [&](uint32_t first, uint32_t end) {
            if (interactive) std::fprintf(stderr, "\r");
            if (!cmd.quiet)
                std::fprintf(stderr, "checkpoint: samples [%u, %u) in %s\n", first, end,
                             exrPath.string().c_str());
        });
    installStopHandlers();

    RenderDescription description{.scene = cmd.scenePath,
                                  .width = scene.film.width,
                                  .height = scene.film.height,
                                  .crop = options.crop,
                                  .firstSample = job.runFirstSample(),
                                  .endSample = job.endSample(),
                                  .filmFirstSample = {},
                                  .resumedFrom = cmd.resume,
                                  .sampler = std::string(samplerKindName(scene.settings.sampler)),
                                  .seed = scene.settings.seed,
                                  .threads = renderThreads(cmd.threads),
                                  .accelerator = cmd.accel,
                                  .film = cmd.film};
    if (job.resumed()) description.filmFirstSample = job.firstSample();
    if (!cmd.quiet) std::fprintf(stderr, "%s\n", describeRender(description).c_str());

    const RenderStats stats = job.run();

    const uint32_t rangeFirst = job.firstSample();
    if (stats.cancelled) {
        const int signal = int(gStopSignal);
        if (interactive) std::fprintf(stderr, "\n");
        if (stats.endSample == rangeFirst && !job.resumed()) {
            std::fprintf(
                stderr,
                "penumbra: stopped by signal %d before the first pass was complete; nothing written\n",
                signal);
            return 128 + signal;
        }
        job.writeFilm(exrPath);
        if (!cmd.noDisplay) writeDisplayImage(job.film(), displayPath, display);
        const std::string exr = shellWord(exrPath.string());
        std::fprintf(stderr,
                     "penumbra: stopped by signal %d; wrote samples [%u, %u) to %s; continue with: penumbra "
                     "render %s%s "
                     "--spp %u --resume %s -o %s\n",
                     signal, rangeFirst, stats.endSample, exrPath.string().c_str(),
                     shellWord(cmd.scenePath).c_str(), filmDefiningOptions(cmd).c_str(), job.endSample(),
                     exr.c_str(), exr.c_str());
        return 128 + signal;
    }
    job.writeFilm(exrPath, contents);
    if (!cmd.noDisplay) writeDisplayImage(job.film(), displayPath, display);

    if (!cmd.quiet) {
        const double seconds = std::max(stats.renderSeconds, 1e-9);
        std::printf(
            "%s\n",
            describeRendered(description, stats.endSample, stats.renderSeconds, stats.buildSeconds).c_str());
        std::printf("  %.2f M samples/s, %.2f M rays/s (%llu camera, %llu bounce, %llu shadow rays)\n",
                    stats.samples / seconds * 1e-6, stats.rays.total() / seconds * 1e-6,
                    (unsigned long long)stats.rays.primary, (unsigned long long)stats.rays.extension,
                    (unsigned long long)stats.rays.shadow);
        // Image textures' cache: only when the scene loaded the texture plugin (it names an image).
        if (texturePluginLoaded()) {
            unsigned long long lookups = 0, files = 0, bytesRead = 0, cacheBytes = 0;
            texturePlugin().counters(&lookups, &files, &bytesRead, &cacheBytes);
            std::printf("  textures: %llu lookups, %llu files, %.1f MB read, %.1f MB in the tile cache\n",
                        lookups, files, bytesRead * 1e-6, cacheBytes * 1e-6);
        }
        if (scene.film.adaptive)
            std::printf(
                "  %s\n",
                describeAdaptiveRender(job.film(), window, *scene.film.adaptive, stats.endSample).c_str());
        std::printf("wrote %s\n", exrPath.string().c_str());
        if (!cmd.noDisplay) std::printf("wrote %s\n", displayPath.string().c_str());
    }
    if (cmd.textureStats && texturePluginLoaded()) {
        std::string text(1 << 16, '\0');
        texturePlugin().statistics(3, text.data(), text.size());
        std::printf("%s\n", text.c_str());
    }
    if (stats.nonFiniteCount > 0) {
        const NonFiniteSample& first = stats.nonFiniteExamples.front();
        std::fprintf(
            stderr,
            "penumbra: warning: %llu samples had non-finite radiance and were recorded as black; "
            "the first, pixel (%d, %d) sample %u, replays with: penumbra render %s --crop %d,%d,%d,%d "
            "--samples %u:%u\n",
            (unsigned long long)stats.nonFiniteCount, first.x, first.y, first.sampleIndex,
            cmd.scenePath.c_str(), first.x, first.x + 1, first.y, first.y + 1, first.sampleIndex,
            first.sampleIndex + 1);
    }
    return 0;
}

// `penumbra convert`: the JSON is written only once the whole scene has been read and built, and
// never over the scene it was read from.
int runConvertCommand(const std::string& scenePath, const std::string& outputPath) {
    const fs::path output(outputPath);
    if (output.extension() != ".json")
        throw InputError(fmt::format(
            "-o: expected a path ending in .json (convert writes penumbra's JSON), got '{}'", outputPath));
    std::error_code ec;
    if (fs::equivalent(output, scenePath, ec))
        throw InputError(fmt::format("-o: {} is the scene being converted; name another output", outputPath));
    const std::string json = convertSceneToJson(scenePath, outputPath);
    writeTextFileAtomically(output, "JSON scene", json);
    std::printf("wrote %s\n", outputPath.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"penumbra: a path / distribution ray tracer (Embree traversal, TBB tiles, OpenEXR output)"};
    app.formatter(std::make_shared<HelpFormatter>());  // before the subcommands, which inherit it
    app.set_version_flag("--version", std::string("penumbra ") + kVersion);
    app.require_subcommand(1);

    RenderCommand cmd;
    CLI::App* renderApp =
        app.add_subcommand("render", "Render a scene file to a scene-linear EXR and a display PNG");
    renderApp->add_option("SCENE", cmd.scenePath, "Scene file (penumbra JSON, see scenes/README.md)")
        ->required();
    renderApp->add_option("--spp", cmd.spp, "Samples per pixel (overrides the scene's film.spp)");
    renderApp->add_option("--seed", cmd.seed, "Seed of all sample values (overrides render.seed)")
        ->check(kSeedText);
    renderApp
        ->add_option("--threads", cmd.threads,
                     "Worker threads; 0 uses every core (the image does not depend on it)")
        ->check(CLI::Range(0, limits::kMaxThreads));
    renderApp->add_option("--res", cmd.resolution, "Resolution WIDTHxHEIGHT (overrides film.resolution)");
    renderApp->add_option("--sampler", cmd.sampler, "stratified (default) or independent");
    renderApp->add_option("--crop", cmd.crop,
                          "Render only pixels x0 <= x < x1, y0 <= y < y1, given as x0,x1,y0,y1 (overrides "
                          "film.crop_window)");
    renderApp->add_option("--samples", cmd.samples,
                          "Render only sample indices FIRST <= i < END, given as FIRST:END");
    renderApp->add_option(
        "-o,--output", cmd.output,
        "Output EXR (default out/SCENE_NAME.exr); a PNG through OpenColorIO is written beside it");
    renderApp->add_flag("--no-display", cmd.noDisplay, "Write only the EXR, no display PNG");
    renderApp->add_flag(
        "--texture-stats", cmd.textureStats,
        "Print OpenImageIO's texture cache statistics after the render (scenes with image textures)");

    renderApp
        ->add_option(
            "--film", cmd.film,
            "What the EXR holds: full (default: image, AOVs and the exact sums; resumable and mergeable, "
            "about 100 bytes a pixel) or beauty (image and AOVs only, about 46 bytes a pixel)")
        ->check(CLI::IsMember({"full", "beauty"}));
    renderApp->add_option(
        "--view", cmd.view,
        "OpenColorIO view of the display PNG: 'Standard' (default, sRGB), 'Filmic' (high dynamic "
        "range), 'False Color' (exposure zones) or 'Raw' (no view transform); see film/README.md");
    renderApp->add_option("--exposure", cmd.exposure, "Exposure of the display PNG in stops (default 0)")
        ->check(CLI::Range(-64.0f, 64.0f));
    renderApp->add_flag("-q,--quiet", cmd.quiet, "No progress line and no summary");
    renderApp->add_option("--accel", cmd.accel, "Traversal backend: embree (default) or bvh (our own)")
        ->check(CLI::IsMember({"embree", "bvh"}));
    renderApp->add_option(
        "--resume", cmd.resume,
        "Continue the film in this EXR (written by render or merge) up to --spp (or END of "
        "--samples FIRST:END, for a film that starts at FIRST); it must come from the same scene, "
        "resolution, seed, sampler, crop and --accel");
    renderApp
        ->add_option(
            "--checkpoint", cmd.checkpointMinutes,
            "Write the film to the output EXR every MINUTES (fractions allowed; 0: after every pass); "
            "SIGINT/SIGTERM always write it before exiting")
        ->check(kCheckpointMinutes);
    renderApp
        ->add_option(
            "--pass-size", cmd.passSize,
            "Sample indices per pass (default: about a million samples a pass); checkpoints and signals "
            "take effect between passes")
        ->check(CLI::PositiveNumber);
    const char* const patchHelp =
        "A JSON merge patch (RFC 7386) applied to the scene in penumbra's format before it is "
        "built, e.g. to change a converted pbrt scene (docs/pbrt-import.md)";
    renderApp->add_option("--patch", cmd.patch, patchHelp);

    renderApp->add_option(
        "--adaptive", cmd.adaptiveThreshold,
        "Adaptive sampling: a pixel stops once the relative standard error of its mean (and its "
        "neighbours') is below THRESHOLD, e.g. 0.02; --spp is then the most a pixel gets "
        "(overrides film.adaptive.threshold)");
    renderApp->add_option(
        "--adaptive-error", cmd.adaptiveError,
        "What --adaptive bounds: relative (default; each pixel's relative standard error, for "
        "display) or absolute (the image's RMSE in scene-linear units, e.g. 0.01, each pixel "
        "sampled in proportion to its noise: the least squared error for the samples; overrides "
        "film.adaptive.error)");
    renderApp->add_option(
        "--min-spp", cmd.minSpp,
        "Samples every pixel gets before adaptive sampling's first decision (default 16; overrides "
        "film.adaptive.min_spp)");

    std::string convertScene, convertOutput;
    CLI::App* convertApp = app.add_subcommand(
        "convert",
        "Convert a pbrt-v4 scene (.pbrt) to penumbra's JSON format; mesh files are referenced in place");
    convertApp->add_option("SCENE", convertScene, "pbrt-v4 scene file")->required();
    convertApp->add_option("-o,--output", convertOutput, "Output JSON scene file")->required();

    std::vector<std::string> mergeParts;
    std::string mergeOutput;
    bool mergeNoDisplay = false, mergeQuiet = false;
    CLI::App* mergeApp = app.add_subcommand(
        "merge",
        "Add partial renders (--samples ranges, --crop windows) of one scene into one EXR, bit for bit as "
        "one render of the union");
    std::string mergeManifest;
    std::optional<int> mergeGroup;
    mergeApp->add_option("PARTS", mergeParts, "EXR files written by penumbra render or merge");
    mergeApp->add_option(
        "-o,--output", mergeOutput,
        "Output EXR (with --manifest, default the manifest's); a PNG through OpenColorIO is written "
        "beside it");
    mergeApp
        ->add_option("--manifest", mergeManifest,
                     "Merge the parts listed in this manifest (written by submit), each checked done")
        ->excludes("PARTS");
    mergeApp->add_option("--group", mergeGroup, "With --manifest: merge only this merge group into its file")
        ->needs("--manifest");
    mergeApp->add_flag("--no-display", mergeNoDisplay, "Write only the EXR, no display PNG");
    mergeApp->add_flag("-q,--quiet", mergeQuiet, "No summary");

    SubmitCommand submitCmd;
    CLI::App* submitApp = app.add_subcommand(
        "submit",
        "Render on a Slurm cluster: a job array of parts (sample ranges or bands of rows) and a merge job "
        "after it, bit for bit one render; see docs/scale-out.md");
    submitApp->add_option("SCENE", submitCmd.scenePath, "Scene file")->required();
    submitApp->add_option("--parts", submitCmd.parts, "Number of parts (array tasks)")
        ->required()
        ->check(CLI::PositiveNumber);
    submitApp
        ->add_option("--by", submitCmd.by,
                     "Split by samples (default: ranges of sample indices) or rows (bands)")
        ->check(CLI::IsMember({"samples", "rows", "tiles"}));
    submitApp->add_option("--spp", submitCmd.spp, "Samples per pixel in all (default the scene's)");
    submitApp
        ->add_option("-o,--output", submitCmd.output, "The merged EXR; the manifest and parts go beside it")
        ->required();
    submitApp->add_option("--partition", submitCmd.slurm.partition,
                          "Slurm partition (default the cluster's)");
    submitApp->add_option("--time", submitCmd.slurm.time,
                          "Time limit of each job, as sbatch --time takes it");
    submitApp
        ->add_option("--cpus-per-task", submitCmd.slurm.cpusPerTask,
                     "Cores per part (default 0: a whole node each, --exclusive)")
        ->check(CLI::NonNegativeNumber);
    submitApp
        ->add_option("--checkpoint", submitCmd.slurm.checkpointMinutes,
                     "Minutes between a part's checkpoints (default 10; 0: after every pass)")
        ->check(kCheckpointMinutes);
    submitApp->add_option("--sbatch", submitCmd.slurm.sbatchArguments,
                          "More sbatch options for every job, e.g. --sbatch=--account=lab (repeatable)");
    submitApp
        ->add_option(
            "--merge-tree-above", submitCmd.mergeTreeAbove,
            "Merge in two levels (groups of about sqrt(N) parts) when there are more parts than this "
            "(default 16)")
        ->check(CLI::NonNegativeNumber);
    submitApp->add_option("--seed", submitCmd.seed, "Seed of all sample values (overrides render.seed)")
        ->check(kSeedText);
    submitApp->add_option("--res", submitCmd.resolution,
                          "Resolution WIDTHxHEIGHT (overrides film.resolution)");
    submitApp->add_option("--sampler", submitCmd.sampler, "stratified (default) or independent");
    submitApp->add_option("--accel", submitCmd.accel, "Traversal backend: embree (default) or bvh")
        ->check(CLI::IsMember({"embree", "bvh"}));
    submitApp->add_option("--pass-size", submitCmd.passSize, "Sample indices per pass of each part's render")
        ->check(CLI::PositiveNumber);
    submitApp->add_flag("--dry-run", submitCmd.dryRun, "Print the batch scripts; write and submit nothing");
    submitApp->add_flag("--resume", submitCmd.resume,
                        "Submit only the parts that are not done (same options as the first submit)");

    std::string statusTarget;
    CLI::App* statusApp = app.add_subcommand(
        "status",
        "Which parts of a submitted render are done, partial, started or missing (from the files alone)");
    statusApp
        ->add_option("OUTPUT", statusTarget, "The merged EXR named to submit -o, or its .parts.json manifest")
        ->required();

    ConvergeCommand convergeCmd;
    CLI::App* convergeApp = app.add_subcommand(
        "converge",
        "Convergence study: error against a reference at each rung of a sample ladder, per sampler; "
        "writes convergence.csv/.json/.png and strip.png");
    convergeApp->add_option("SCENE", convergeCmd.scenePath, "Scene file")->required();
    convergeApp->add_option("--spp", convergeCmd.spp, "Rungs, e.g. 1,2,4,...,1024 (default 1,2,4,...,256)");
    convergeApp->add_option("--sampler", convergeCmd.samplers,
                            "Samplers to compare (default stratified,independent)");
    convergeApp->add_option(
        "--strategy", convergeCmd.strategies,
        "Light strategies to compare, each with every sampler: mis (both, weighted by the power "
        "heuristic), bsdf (BSDF sampling alone), light (light sampling alone); default the scene's");
    convergeApp->add_option("--reference", convergeCmd.reference,
                            "Reference image (a penumbra EXR, or any image with R, G, B of the same size)");
    convergeApp->add_option(
        "--reference-spp", convergeCmd.referenceSpp,
        "Samples per pixel of the rendered reference (default 8 x the top rung, at most 8192)");
    convergeApp->add_option("--seeds", convergeCmd.seeds,
                            "Renders per sampler with seeds S, S+1, ... (error bars)");
    convergeApp->add_option("--seed", convergeCmd.seed, "First seed (default: the scene's)")
        ->check(kSeedText);
    convergeApp->add_option(
        "--freeze", convergeCmd.freeze,
        "Fix dimensions at their centre to attribute noise: lens, time, light, pixel (comma-separated)");
    convergeApp->add_option("--res", convergeCmd.resolution,
                            "Resolution WIDTHxHEIGHT (overrides film.resolution)");
    convergeApp->add_option("--strip", convergeCmd.strip,
                            "Window x0,x1,y0,y1 shown in strip.png (default: centred square)");
    convergeApp->add_option("--threads", convergeCmd.threads, "Worker threads; 0 uses every core")
        ->check(CLI::Range(0, limits::kMaxThreads));
    convergeApp->add_option("--accel", convergeCmd.accel, "Traversal backend: embree (default) or bvh")
        ->check(CLI::IsMember({"embree", "bvh"}));
    convergeApp->add_option("-o,--output", convergeCmd.output, "Output folder")->required();
    convergeApp->add_option("--patch", convergeCmd.patch, patchHelp);
    convergeApp->add_flag("--no-plot", convergeCmd.noPlot, "Do not run tools/plot_convergence.py");
    convergeApp->add_flag("-q,--quiet", convergeCmd.quiet, "No progress lines");
    convergeApp->add_flag(
        "--adaptive", convergeCmd.adaptive,
        "Also adaptive renders (up to 4x the top rung per pixel) at thresholds mapped to the rungs "
        "(the fixed render's median relative error at each), and the time and samples each needs to "
        "reach the fixed rungs' RMSE");
    convergeApp->add_option("--min-spp", convergeCmd.minSpp,
                            "Samples before the adaptive renders' first decision (default 16)");
    convergeApp->add_option(
        "--adaptive-error", convergeCmd.adaptiveError,
        "The adaptive renders' criterion: relative (default) or absolute (each rung's threshold is "
        "then the RMSE the fixed render reached there)");

    std::string crosscheckScene, crosscheckPatch;
    CrosscheckOptions crosscheckOptions;
    bool crosscheckJson = false;
    CLI::App* crosscheckApp = app.add_subcommand(
        "crosscheck",
        "Trace the same rays through our BVH and Embree and explain every disagreement; exits with "
        "status 3 when a mismatch is unexplained or a self-intersection");
    crosscheckApp->add_option("SCENE", crosscheckScene, "Scene file")->required();
    crosscheckApp
        ->add_option("--rays", crosscheckOptions.rays,
                     "Rays in all, a quarter of each kind (default 1000000)")
        ->check(CLI::PositiveNumber);
    crosscheckApp->add_option("--seed", crosscheckOptions.seed, "Seed of the ray set (default 0)")
        ->check(kSeedText);
    crosscheckApp->add_flag("--json", crosscheckJson, "Machine-readable output");
    crosscheckApp->add_option("--patch", crosscheckPatch, patchHelp);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(
            stderr,
            "penumbra: error: %s\nRun 'penumbra --help' or 'penumbra render --help' for the options.\n",
            e.what());
        return 2;
    }

    try {
        if (renderApp->parsed()) return runRender(cmd);
        if (crosscheckApp->parsed())
            return runCrosscheckCommand(crosscheckScene, crosscheckPatch, crosscheckOptions, crosscheckJson);
        if (mergeApp->parsed()) {
            if (!mergeManifest.empty())
                return runManifestMerge(mergeManifest, mergeGroup, mergeOutput, mergeNoDisplay, mergeQuiet);
            if (mergeParts.empty() || mergeOutput.empty())
                throw InputError("merge: expected PART.exr... -o OUT.exr, or --manifest OUT.parts.json");
            return runMergeCommand(mergeParts, mergeOutput, mergeNoDisplay, mergeQuiet);
        }
        if (submitApp->parsed()) {
            if (submitCmd.by == "tiles")
                submitCmd.by = "rows";  // bands of rows are the tiles of a split render
            return runSubmitCommand(submitCmd);
        }
        if (statusApp->parsed()) return runStatusCommand(statusTarget);
        if (convergeApp->parsed()) return runConvergeCommand(convergeCmd);
        if (convertApp->parsed()) return runConvertCommand(convertScene, convertOutput);
    } catch (const InputError& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
