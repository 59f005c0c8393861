// penumbra: the command-line program.
//
//   penumbra render SCENE [--spp N] [--seed S] [--threads N] [--res WxH] [--accel embree|bvh]
//                   [--adaptive T [--min-spp N]] [-o PATH] ...
//   penumbra crosscheck SCENE [--rays N] [--seed S] [--json]
//   penumbra merge PART.exr... -o OUT.exr
//   penumbra converge SCENE --spp 1,2,4,...,1024 [--sampler ...] [--reference REF.exr] -o DIR
//
// Bad input is reported as "penumbra: error: FILE:LINE: message" (or a JSON pointer instead of
// the line) with a non-zero exit status, and no output file is written.

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "core/error.h"
#include "core/input_limits.h"
#include "film/film.h"
#include "film/image_output.h"
#include "renderer/render.h"
#include "renderer/render_job.h"
#include "scenes/scene_loader.h"
#include "tools/adaptive_options.h"
#include "tools/cli_numbers.h"
#include "tools/split_text.h"
#include "tools/converge.h"
#include "tools/crosscheck.h"
#include "tools/merge_command.h"

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
    std::string crop;        // "x0,x1,y0,y1"
    std::string samples;     // "a:b"
    std::string output;
    bool noDisplay = false;
    bool quiet = false;
    std::string accel = "embree";
    std::string resume;                       // a film to continue up to --spp
    std::optional<double> checkpointMinutes;  // write the film every so often (0: after every pass)
    std::optional<uint32_t> passSize;         // sample indices per pass
    std::optional<double> adaptiveThreshold;  // --adaptive
    std::optional<int64_t> minSpp;            // --min-spp
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

// Command-line integers: 1 to 2^30 (a positive count or size), or 0 to 2^30 (an index or a pixel).
int parsePositive(const std::string& option, const std::string& text) {
    return int(parseIntegerOption(option, text, 1, int64_t(1) << 30));
}
int parseNonNegative(const std::string& option, const std::string& text) {
    return int(parseIntegerOption(option, text, 0, int64_t(1) << 30));
}

// Prints a one-line progress bar with an ETA on a terminal, at most ten times a second.
class ProgressLine {
public:
    explicit ProgressLine(bool enabled) : enabled_(enabled), start_(Clock::now()) {}
    void update(size_t done, size_t total) {
        if (!enabled_) return;
        const auto now = Clock::now();
        if (done != total && now - lastPrint_ < std::chrono::milliseconds(100)) return;
        lastPrint_ = now;
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        const double fraction = total ? double(done) / double(total) : 1.0;
        const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
        constexpr int kWidth = 30;
        const int filled = int(fraction * kWidth);
        std::fprintf(stderr, "\r[%s%s] %5.1f%%  elapsed %.1f s  ETA %.1f s ", std::string(filled, '=').c_str(),
                     std::string(kWidth - filled, ' ').c_str(), 100.0 * fraction, elapsed, eta);
        if (done == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

private:
    using Clock = std::chrono::steady_clock;
    bool enabled_;
    Clock::time_point start_, lastPrint_{};
};

int runRender(const RenderCommand& cmd) {
    Scene scene = loadScene(cmd.scenePath);
    if (cmd.spp) {
        if (*cmd.spp <= 0) throw InputError(fmt::format("--spp: expected a positive integer, got {}", *cmd.spp));
        scene.film.samplesPerPixel = *cmd.spp;
    }
    if (cmd.seed) scene.settings.seed = *cmd.seed;
    if (!cmd.sampler.empty()) {
        if (cmd.sampler == "stratified") scene.settings.sampler = SamplerKind::Stratified;
        else if (cmd.sampler == "independent") scene.settings.sampler = SamplerKind::Independent;
        else throw InputError(fmt::format("--sampler: expected 'stratified' or 'independent', got '{}'", cmd.sampler));
    }
    if (!cmd.resolution.empty()) {
        const auto parts = splitText(cmd.resolution, 'x');
        if (parts.size() != 2) throw InputError(fmt::format("--res: expected WIDTHxHEIGHT, got '{}'", cmd.resolution));
        // The scene's own limit (film.resolution), not 2^30.
        scene.film.width = int(parseIntegerOption("--res", parts[0], 1, limits::kMaxImageSide));
        scene.film.height = int(parseIntegerOption("--res", parts[1], 1, limits::kMaxImageSide));
    }
    applyAdaptiveOptions(scene, cmd.adaptiveThreshold, cmd.minSpp);

    RenderOptions options;
    options.threads = cmd.threads;
    options.accelerator = cmd.accel == "bvh" ? AcceleratorKind::Bvh : AcceleratorKind::Embree;
    options.endSample = uint32_t(scene.film.samplesPerPixel);
    if (!cmd.samples.empty()) {
        const auto parts = splitText(cmd.samples, ':');
        if (parts.size() != 2) throw InputError(fmt::format("--samples: expected FIRST:END, got '{}'", cmd.samples));
        options.firstSample = uint32_t(parseNonNegative("--samples", parts[0]));
        options.endSample = uint32_t(parsePositive("--samples", parts[1]));
        if (options.firstSample >= options.endSample)
            throw InputError(fmt::format("--samples: FIRST must be below END, got '{}'", cmd.samples));
        if (scene.film.adaptive && options.firstSample > 0)
            throw InputError("--samples: an adaptive render (--adaptive, film.adaptive) starts at sample 0, where its "
                             "pixels' decisions start; use --checkpoint and --resume to split it in time");
    }
    if (!cmd.crop.empty()) {
        const auto parts = splitText(cmd.crop, ',');
        if (parts.size() != 4) throw InputError(fmt::format("--crop: expected x0,x1,y0,y1, got '{}'", cmd.crop));
        options.crop = PixelWindow{parseNonNegative("--crop", parts[0]), parseNonNegative("--crop", parts[1]),
                                   parseNonNegative("--crop", parts[2]), parseNonNegative("--crop", parts[3])};
    }

    fs::path exrPath = cmd.output.empty() ? fs::path("out") / (fs::path(cmd.scenePath).stem().string() + ".exr")
                                          : fs::path(cmd.output);
    if (exrPath.extension() != ".exr")
        throw InputError(fmt::format("-o: expected a path ending in .exr, got '{}'", exrPath.string()));
    const fs::path displayPath = fs::path(exrPath).replace_extension(".png");

    const bool interactive = !cmd.quiet && isatty(STDERR_FILENO);
    ProgressLine progress(interactive);
    options.progress = [&](size_t done, size_t total) { progress.update(done, total); };

    // Passes: about a million samples each unless --pass-size says otherwise (defaultPassSize).
    const PixelWindow window = options.crop.value_or(PixelWindow{0, scene.film.width, 0, scene.film.height});
    const uint64_t windowPixels = uint64_t(std::max(1, window.width())) * uint64_t(std::max(1, window.height()));
    options.passSize = cmd.passSize ? *cmd.passSize : defaultPassSize(windowPixels);
    if (options.passSize == 0) throw InputError("--pass-size: expected a positive integer");
    options.cancel = &gStopRequested;

    RenderJob job(scene, SceneSource::of(cmd.scenePath, scene), options);
    // --resume: continue the film in the file from where it ends up to --spp (the same samples,
    // so the result is the same bit for bit as one render).
    if (!cmd.resume.empty()) {
        if (!cmd.samples.empty())
            throw InputError("--resume continues a film up to --spp; it cannot be combined with --samples");
        job.resumeFrom(cmd.resume);
    }
    if (cmd.checkpointMinutes)
        job.checkpointEvery(*cmd.checkpointMinutes, exrPath, [&](uint32_t first, uint32_t end) {
            if (interactive) std::fprintf(stderr, "\r");
            if (!cmd.quiet) std::fprintf(stderr, "checkpoint: samples [%u, %u) in %s\n", first, end, exrPath.string().c_str());
        });
    installStopHandlers();

    const RenderStats stats = job.run();

    const uint32_t rangeFirst = job.firstSample();
    if (stats.cancelled) {
        const int signal = int(gStopSignal);
        if (interactive) std::fprintf(stderr, "\n");
        if (stats.endSample == rangeFirst && !job.resumed()) {
            std::fprintf(stderr, "penumbra: stopped by signal %d before the first pass was complete; nothing written\n",
                         signal);
            return 128 + signal;
        }
        job.writeFilm(exrPath);
        if (!cmd.noDisplay) writeDisplayImage(job.film(), displayPath);
        std::fprintf(stderr,
                     "penumbra: stopped by signal %d; wrote samples [%u, %u) to %s; continue with: penumbra render %s "
                     "--spp %u --resume %s -o %s (and the same --seed, --sampler, --res, --crop, --accel, --adaptive, --min-spp)\n",
                     signal, rangeFirst, stats.endSample, exrPath.string().c_str(), cmd.scenePath.c_str(),
                     job.endSample(), exrPath.string().c_str(), exrPath.string().c_str());
        return 128 + signal;
    }
    job.writeFilm(exrPath);
    if (!cmd.noDisplay) writeDisplayImage(job.film(), displayPath);

    if (!cmd.quiet) {
        const double seconds = std::max(stats.renderSeconds, 1e-9);
        std::printf("rendered %dx%d, samples %u:%u (%s sampler, seed %llu) in %.2f s (scene build %.2f s)\n",
                    scene.film.width, scene.film.height, rangeFirst, stats.endSample,
                    std::string(samplerKindName(scene.settings.sampler)).c_str(), (unsigned long long)scene.settings.seed, stats.renderSeconds,
                    stats.buildSeconds);
        std::printf("  %.2f M samples/s, %.2f M rays/s (%llu camera, %llu bounce, %llu shadow rays)\n",
                    stats.samples / seconds * 1e-6, stats.rays.total() / seconds * 1e-6,
                    (unsigned long long)stats.rays.primary, (unsigned long long)stats.rays.extension,
                    (unsigned long long)stats.rays.shadow);
        if (scene.film.adaptive)
            std::printf("  %s\n", describeAdaptiveRender(job.film(), window, *scene.film.adaptive, stats.endSample).c_str());
        std::printf("wrote %s\n", exrPath.string().c_str());
        if (!cmd.noDisplay) std::printf("wrote %s\n", displayPath.string().c_str());
    }
    if (stats.nonFiniteCount > 0) {
        const NonFiniteSample& first = stats.nonFiniteExamples.front();
        std::fprintf(stderr,
                     "penumbra: warning: %llu samples had non-finite radiance and were recorded as black; "
                     "the first, pixel (%d, %d) sample %u, replays with: penumbra render %s --crop %d,%d,%d,%d "
                     "--samples %u:%u\n",
                     (unsigned long long)stats.nonFiniteCount, first.x, first.y, first.sampleIndex,
                     cmd.scenePath.c_str(), first.x, first.x + 1, first.y, first.y + 1, first.sampleIndex,
                     first.sampleIndex + 1);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"penumbra: a path / distribution ray tracer (Embree traversal, TBB tiles, OpenEXR output)"};
    app.set_version_flag("--version", std::string("penumbra ") + kVersion);
    app.require_subcommand(1);

    RenderCommand cmd;
    CLI::App* renderApp = app.add_subcommand("render", "Render a scene file to a scene-linear EXR and a display PNG");
    renderApp->add_option("SCENE", cmd.scenePath, "Scene file (penumbra JSON, see scenes/README.md)")->required();
    renderApp->add_option("--spp", cmd.spp, "Samples per pixel (overrides the scene's film.spp)");
    renderApp->add_option("--seed", cmd.seed, "Seed of all sample values (overrides render.seed)")->check(kSeedText);
    renderApp->add_option("--threads", cmd.threads, "Worker threads; 0 uses every core (the image does not depend on it)")
        ->check(CLI::Range(0, limits::kMaxThreads));
    renderApp->add_option("--res", cmd.resolution, "Resolution WIDTHxHEIGHT (overrides film.resolution)");
    renderApp->add_option("--sampler", cmd.sampler, "stratified (default) or independent");
    renderApp->add_option("--crop", cmd.crop, "Render only pixels x0 <= x < x1, y0 <= y < y1, given as x0,x1,y0,y1");
    renderApp->add_option("--samples", cmd.samples, "Render only sample indices FIRST <= i < END, given as FIRST:END");
    renderApp->add_option("-o,--output", cmd.output,
                          "Output EXR (default out/SCENE_NAME.exr); a PNG through OpenColorIO is written beside it");
    renderApp->add_flag("--no-display", cmd.noDisplay, "Write only the EXR, no display PNG");
    renderApp->add_flag("-q,--quiet", cmd.quiet, "No progress line and no summary");
    renderApp->add_option("--accel", cmd.accel, "Traversal backend: embree (default) or bvh (our own)")
        ->check(CLI::IsMember({"embree", "bvh"}));
    renderApp->add_option("--resume", cmd.resume,
                          "Continue the film in this EXR (written by render or merge) up to --spp; it must come from "
                          "the same scene, resolution, seed, sampler, crop and --accel");
    renderApp->add_option("--checkpoint", cmd.checkpointMinutes,
                          "Write the film to the output EXR every MINUTES (fractions allowed; 0: after every pass); "
                          "SIGINT/SIGTERM always write it before exiting");
    renderApp->add_option("--pass-size", cmd.passSize,
                          "Sample indices per pass (default: about a million samples a pass); checkpoints and signals "
                          "take effect between passes")
        ->check(CLI::PositiveNumber);
    renderApp->add_option("--adaptive", cmd.adaptiveThreshold,
                          "Adaptive sampling: a pixel stops once the relative standard error of its mean (and its "
                          "neighbours') is below THRESHOLD, e.g. 0.02; --spp is then the most a pixel gets "
                          "(overrides film.adaptive.threshold)");
    renderApp->add_option("--min-spp", cmd.minSpp,
                          "Samples every pixel gets before adaptive sampling's first decision (default 16; overrides "
                          "film.adaptive.min_spp)");

    std::vector<std::string> mergeParts;
    std::string mergeOutput;
    bool mergeNoDisplay = false, mergeQuiet = false;
    CLI::App* mergeApp = app.add_subcommand(
        "merge", "Add partial renders (--samples ranges, --crop windows) of one scene into one EXR, bit for bit as "
                 "one render of the union");
    mergeApp->add_option("PARTS", mergeParts, "EXR files written by penumbra render or merge")->required();
    mergeApp->add_option("-o,--output", mergeOutput, "Output EXR; a PNG through OpenColorIO is written beside it")
        ->required();
    mergeApp->add_flag("--no-display", mergeNoDisplay, "Write only the EXR, no display PNG");
    mergeApp->add_flag("-q,--quiet", mergeQuiet, "No summary");

    ConvergeCommand convergeCmd;
    CLI::App* convergeApp = app.add_subcommand(
        "converge", "Convergence study: error against a reference at each rung of a sample ladder, per sampler; "
                    "writes convergence.csv/.json/.png and strip.png");
    convergeApp->add_option("SCENE", convergeCmd.scenePath, "Scene file")->required();
    convergeApp->add_option("--spp", convergeCmd.spp, "Rungs, e.g. 1,2,4,...,1024 (default 1,2,4,...,256)");
    convergeApp->add_option("--sampler", convergeCmd.samplers, "Samplers to compare (default stratified,independent)");
    convergeApp->add_option("--strategy", convergeCmd.strategies,
                            "Light strategies to compare, each with every sampler: mis (both, weighted by the power "
                            "heuristic), bsdf (BSDF sampling alone), light (light sampling alone); default the scene's");
    convergeApp->add_option("--reference", convergeCmd.reference,
                            "Reference image (a penumbra EXR, or any image with R, G, B of the same size)");
    convergeApp->add_option("--reference-spp", convergeCmd.referenceSpp,
                            "Samples per pixel of the rendered reference (default 8 x the top rung, at most 8192)");
    convergeApp->add_option("--seeds", convergeCmd.seeds, "Renders per sampler with seeds S, S+1, ... (error bars)");
    convergeApp->add_option("--seed", convergeCmd.seed, "First seed (default: the scene's)")->check(kSeedText);
    convergeApp->add_option("--freeze", convergeCmd.freeze,
                            "Fix dimensions at their centre to attribute noise: lens, time, light, pixel (comma-separated)");
    convergeApp->add_option("--res", convergeCmd.resolution, "Resolution WIDTHxHEIGHT (overrides film.resolution)");
    convergeApp->add_option("--strip", convergeCmd.strip, "Window x0,x1,y0,y1 shown in strip.png (default: centred square)");
    convergeApp->add_option("--threads", convergeCmd.threads, "Worker threads; 0 uses every core")
        ->check(CLI::Range(0, limits::kMaxThreads));
    convergeApp->add_option("--accel", convergeCmd.accel, "Traversal backend: embree (default) or bvh")
        ->check(CLI::IsMember({"embree", "bvh"}));
    convergeApp->add_option("-o,--output", convergeCmd.output, "Output folder")->required();
    convergeApp->add_flag("--no-plot", convergeCmd.noPlot, "Do not run tools/plot_convergence.py");
    convergeApp->add_flag("-q,--quiet", convergeCmd.quiet, "No progress lines");
    convergeApp->add_flag("--adaptive", convergeCmd.adaptive,
                          "Also adaptive renders (up to 4x the top rung per pixel) at thresholds mapped to the rungs "
                          "(the fixed render's median relative error at each), and the time and samples each needs to "
                          "reach the fixed rungs' RMSE");
    convergeApp->add_option("--min-spp", convergeCmd.minSpp, "Samples before the adaptive renders' first decision (default 16)");

    std::string crosscheckScene;
    CrosscheckOptions crosscheckOptions;
    bool crosscheckJson = false;
    CLI::App* crosscheckApp = app.add_subcommand(
        "crosscheck", "Trace the same rays through our BVH and Embree and explain every disagreement; exits with "
                      "status 3 when a mismatch is unexplained or a self-intersection");
    crosscheckApp->add_option("SCENE", crosscheckScene, "Scene file")->required();
    crosscheckApp->add_option("--rays", crosscheckOptions.rays, "Rays in all, a quarter of each kind (default 1000000)")
        ->check(CLI::PositiveNumber);
    crosscheckApp->add_option("--seed", crosscheckOptions.seed, "Seed of the ray set (default 0)")->check(kSeedText);
    crosscheckApp->add_flag("--json", crosscheckJson, "Machine-readable output");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "penumbra: error: %s\nRun 'penumbra --help' or 'penumbra render --help' for the options.\n", e.what());
        return 2;
    }

    try {
        if (renderApp->parsed()) return runRender(cmd);
        if (crosscheckApp->parsed()) return runCrosscheckCommand(crosscheckScene, crosscheckOptions, crosscheckJson);
        if (mergeApp->parsed()) return runMergeCommand(mergeParts, mergeOutput, mergeNoDisplay, mergeQuiet);
        if (convergeApp->parsed()) return runConvergeCommand(convergeCmd);
    } catch (const InputError& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
