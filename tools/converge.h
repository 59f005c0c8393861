// `penumbra converge`: convergence studies. For each sampler (and seed), ONE render whose film is
// snapshotted at every rung of a sample ladder: the rungs are nested prefixes of the same samples
// (render [0, 1), snapshot, [1, 2), snapshot, [2, 4), ...), not separate renders. Each snapshot is
// compared with a reference (a given EXR, or a render at high spp with another seed): MSE,
// relative MSE (per pixel and channel (x - r)^2 / (r^2 + 1e-2), averaged) and RMSE, with the time
// it took to reach the rung. The slope of log MSE against log spp (least squares) tells the
// convergence rate: -1 for independent samples, steeper where stratification pays.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "accel/traversal.h"
#include "core/sampler.h"
#include "film/film.h"
#include "film/film_exr.h"
#include "renderer/render_job.h"
#include "scenes/scene.h"
#include "tools/adaptive_study.h"

namespace penumbra {

struct ConvergenceOptions {
    std::vector<uint32_t> rungs;  // samples per pixel, ascending
    std::vector<SamplerKind> samplers{SamplerKind::Stratified, SamplerKind::Independent};
    // Light strategies to compare (integrator "strategy"); empty: the scene's own. Each sampler is
    // studied with each strategy; the reference always uses MIS.
    std::vector<LightStrategy> strategies;
    int seeds = 1;            // seeds scene seed, +1, ... (K > 1 gives error bars)
    uint32_t frozenDims = 0;  // PixelSample::dimBit mask (--freeze), for the study and the reference
    std::optional<std::filesystem::path> referencePath;  // else a reference is rendered:
    uint32_t referenceSpp = 0;  // 0: 8 x the top rung, at most kMaxReferenceSpp (and at least the top rung)
    int threads = 0;
    AcceleratorKind accelerator = AcceleratorKind::Embree;
    std::optional<PixelWindow> stripWindow;       // the crop shown in strip.png; default: a centred square
    std::function<void(const std::string&)> log;  // progress lines; may be empty
    SceneSource source;                           // recorded in the rendered reference's film
    // --adaptive: adaptive renders at thresholds mapped to the rungs (tools/adaptive_study.h),
    // for each sampler and strategy with the first seed.
    bool adaptive = false;
    uint32_t adaptiveMinSamples = 16;
    // The adaptive renders' criterion; with the absolute one, a rung's threshold is the RMSE the
    // fixed render reached there (against the reference) rather than its median relative error.
    AdaptiveError adaptiveError = AdaptiveError::Relative;

    static constexpr uint32_t kMaxReferenceSpp = 8192;
};

struct RungError {
    uint32_t spp = 0;
    double mse = 0, relMse = 0, rmse = 0;
    double seconds = 0;  // render time from the first sample to this rung (snapshots excluded)
};

struct SeedRun {
    uint64_t seed = 0;
    std::vector<RungError> rungs;
    double slope = 0;  // of this seed's log MSE against log spp
};

struct SamplerStudy {
    SamplerKind sampler = SamplerKind::Stratified;
    LightStrategy strategy = LightStrategy::Mis;
    std::string name;                       // "stratified", or "stratified mis" when strategies are compared
    std::vector<SeedRun> runs;              // one per seed
    std::vector<RungError> mean;            // per rung: averages over the seeds
    std::vector<double> mseStd, relMseStd;  // per rung: standard deviation over the seeds (0 for one seed)
    double slope = 0;                       // least squares of log(mean MSE) against log(spp)
    double slopeStd = 0;                    // standard deviation of the per-seed slopes (0 for one seed)
    std::vector<std::vector<float>> strip;  // seed 0's mean RGB in the strip window at each rung
    std::vector<float>
        adaptiveThresholds;  // --adaptive: seed 0's median relative error (or RMSE) at each rung
    std::optional<AdaptiveStudy> adaptive;  // --adaptive: the adaptive runs and the equal-error table
};

struct ConvergenceReport {
    int width = 0, height = 0;
    std::vector<uint32_t> rungs;
    uint32_t frozenDims = 0;
    // The reference: a file, or a render (stratified sampler).
    std::string referenceSource;  // the file, or "rendered"
    uint32_t referenceSpp = 0;    // 0 for a file without penumbra metadata
    uint64_t referenceSeed = 0;
    double referenceSeconds = 0;
    // Mean variance of the reference's mean per pixel and channel (0 when unknown): its own
    // contribution to every measured MSE, the floor of the curves.
    double referenceMseFloor = 0;
    std::vector<float> reference;           // mean RGB, row-major
    std::optional<FilmFile> referenceFilm;  // when the reference was rendered
    PixelWindow stripWindow;
    std::vector<SamplerStudy> studies;
};

// Least-squares slope of log(y) against log(x).
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y);

// Runs the study on `scene` as given (resolution, integrator, seed). Throws InputError for bad
// options (no rungs, a reference of another size, ...).
ConvergenceReport runConvergence(const Scene& scene, const ConvergenceOptions& options);

// Writes DIR/convergence.csv, DIR/convergence.json and DIR/strip.png (rows: samplers in order;
// columns: the rungs ascending, then the reference).
void writeConvergenceReport(const ConvergenceReport& report, const std::string& sceneFile,
                            const std::filesystem::path& dir);

// Parses "1,2,4,...,1024" (a "..." continues the ratio of the two numbers before it) or "1,4,16".
std::vector<uint32_t> parseRungs(const std::string& text);

// Parses "lens,time,light,pixel" into a PixelSample::dimBit mask.
uint32_t parseFrozenDims(const std::string& text);
std::string frozenDimsName(uint32_t mask);

// `penumbra converge ...`; returns the exit status.
struct ConvergeCommand {
    std::string scenePath;
    std::string patch;  // a JSON merge patch applied to the scene (SceneFileOptions::patch); empty: none
    std::string spp = "1,2,4,...,256";
    std::string samplers = "stratified,independent";
    std::string strategies;  // "mis,bsdf,light"; empty: the scene's own
    std::string reference;
    std::optional<uint32_t> referenceSpp;
    int seeds = 1;
    std::optional<uint64_t> seed;
    std::string freeze;
    std::string resolution;
    std::string strip;
    std::string output;
    int threads = 0;
    std::string accel = "embree";
    bool noPlot = false;
    bool quiet = false;
    bool adaptive = false;          // --adaptive
    std::optional<int64_t> minSpp;  // --min-spp
    std::string adaptiveError;      // --adaptive-error (empty: relative)
};
int runConvergeCommand(const ConvergeCommand& cmd);

}  // namespace penumbra
