#include "tools/converge.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <numeric>

#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/resource_paths.h"
#include "film/atomic_file.h"
#include "film/display_image.h"
#include "film/film_exr.h"
#include "film/image_plugin_loader.h"
#include "formats/scene_file.h"
#include "renderer/render.h"
#include "tools/cli_numbers.h"
#include "tools/run_program.h"
#include "tools/split_text.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

double secondsOf(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Error of a mean image against the reference, over all pixels and channels.
RungError measure(const Film& film, const std::vector<float>& reference) {
    double squared = 0, relative = 0;
    size_t i = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Rgb m = film.at(x, y).mean();
            for (int c = 0; c < 3; ++c, ++i) {
                const double r = reference[i];
                const double d = double(m[c]) - r;
                squared += d * d;
                relative += d * d / (r * r + 1e-2);
            }
        }
    RungError e;
    const double n = double(reference.size());
    e.mse = squared / n;
    e.relMse = relative / n;
    e.rmse = std::sqrt(e.mse);
    return e;
}

// The reference from a file: a penumbra film (exact means, and its own variance), or any image
// with R, G and B channels (e.g. another renderer's converged EXR), read through the image plugin.
void loadReference(const std::filesystem::path& path, int width, int height, ConvergenceReport& report) {
    SourceLocation where;
    where.file = path.string();
    InputFile(path, "reference image", UINT64_MAX);  // a regular file: a FIFO would block the readers
    auto checkSize = [&](int fileWidth, int fileHeight) {
        if (fileWidth != width || fileHeight != height)
            throw InputError(
                where, fmt::format("the reference is {}x{} but the study renders {}x{} (set --res to the "
                                   "reference's size, or render a reference at this size)",
                                   fileWidth, fileHeight, width, height));
    };
    report.referenceSource = path.string();
    report.reference.assign(size_t(width) * height * 3, 0.0f);
    if (isPenumbraFilm(path)) {
        const FilmFile file = readFilmExr(path);
        checkSize(file.film.width(), file.film.height());
        if (file.metadata.crop)
            throw InputError(where,
                             "the reference covers only a crop of the image; a reference must cover it all");
        report.referenceSpp = file.metadata.endSample - file.metadata.firstSample;
        report.referenceSeed = file.metadata.seed;
        report.referenceSeconds = file.metadata.renderSeconds;
        double floor = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const Rgb m = file.film.at(x, y).mean(), v = file.film.at(x, y).varianceOfMean();
                for (int c = 0; c < 3; ++c) {
                    report.reference[(size_t(y) * width + x) * 3 + c] = m[c];
                    floor += v[c];
                }
            }
        report.referenceMseFloor = floor / double(report.reference.size());
        return;
    }
    const PenumbraImagePlugin& plugin = imagePlugin();
    char error[1024];
    PenumbraImageInfo info;
    if (!plugin.readInfo(path.c_str(), &info, error, sizeof error))
        throw InputError(where, fmt::format("cannot read the reference image: {}", error));
    checkSize(info.fullWidth, info.fullHeight);
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
        if (info.rgbChannel[c] < 0)
            throw InputError(where, fmt::format("the reference image has no channel '{}'", names[c]));
    if (info.x != 0 || info.y != 0 || info.width != width || info.height != height)
        throw InputError(where, "the reference image's data window must be the whole image");
    if (!plugin.readRgb(path.c_str(), report.reference.data(), error, sizeof error))
        throw InputError(where, fmt::format("cannot read the reference image: {}", error));
}

double meanOf(const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}
double stdOf(const std::vector<double>& v) {
    if (v.size() < 2) return 0.0;
    const double m = meanOf(v);
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / double(v.size() - 1));
}

}  // namespace

double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
    std::vector<double> lx, ly;
    for (size_t i = 0; i < x.size() && i < y.size(); ++i)
        if (x[i] > 0 && y[i] > 0) {
            lx.push_back(std::log(x[i]));
            ly.push_back(std::log(y[i]));
        }
    if (lx.size() < 2) return 0.0;
    const double mx = meanOf(lx), my = meanOf(ly);
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < lx.size(); ++i) {
        sxy += (lx[i] - mx) * (ly[i] - my);
        sxx += (lx[i] - mx) * (lx[i] - mx);
    }
    return sxx > 0 ? sxy / sxx : 0.0;
}

std::vector<uint32_t> parseRungs(const std::string& text) {
    std::vector<uint32_t> rungs;
    const std::vector<std::string> parts = splitText(text, ',');
    for (size_t i = 0; i < parts.size(); ++i) {
        if (parts[i] == "...") {
            if (rungs.size() < 2 || i + 1 >= parts.size() ||
                rungs[rungs.size() - 1] % rungs[rungs.size() - 2] != 0 ||
                rungs[rungs.size() - 1] <= rungs[rungs.size() - 2])
                throw InputError(
                    fmt::format("--spp: '...' must follow two numbers of which the second is a multiple "
                                "of the first, and come before a last number, as in 1,2,4,...,1024; got '{}'",
                                text));
            const uint32_t ratio = rungs[rungs.size() - 1] / rungs[rungs.size() - 2];
            const uint32_t last = uint32_t(parseIntegerOption("--spp", parts[i + 1], 1, 1 << 24));
            for (uint64_t v = uint64_t(rungs.back()) * ratio; v < last; v *= ratio)
                rungs.push_back(uint32_t(v));
            continue;
        }
        rungs.push_back(uint32_t(parseIntegerOption("--spp", parts[i], 1, 1 << 24)));
    }
    for (size_t i = 1; i < rungs.size(); ++i)
        if (rungs[i] <= rungs[i - 1])
            throw InputError(fmt::format("--spp: the rungs must increase, got '{}'", text));
    if (rungs.empty()) throw InputError("--spp: no rungs");
    return rungs;
}

namespace {
struct FrozenName {
    const char* name;
    Dim dim;
};
constexpr FrozenName kFrozenNames[] = {
    {"pixel", Dim::Pixel}, {"lens", Dim::Lens}, {"time", Dim::Time}, {"light", Dim::LightPosition}};
}  // namespace

uint32_t parseFrozenDims(const std::string& text) {
    uint32_t mask = 0;
    if (text.empty()) return 0;
    for (const std::string& name : splitText(text, ',')) {
        bool known = false;
        for (const FrozenName& f : kFrozenNames)
            if (name == f.name) {
                mask |= PixelSample::dimBit(f.dim);
                known = true;
            }
        if (!known)
            throw InputError(
                fmt::format("--freeze: unknown dimension '{}' (expected lens, time, light or pixel)", name));
    }
    return mask;
}

std::string frozenDimsName(uint32_t mask) {
    std::string out;
    for (const FrozenName& f : kFrozenNames)
        if (mask & PixelSample::dimBit(f.dim)) {
            if (!out.empty()) out += ',';
            out += f.name;
        }
    return out;
}

ConvergenceReport runConvergence(const Scene& scene, const ConvergenceOptions& options) {
    if (options.rungs.empty()) throw InputError("converge: no rungs (--spp)");
    for (size_t i = 1; i < options.rungs.size(); ++i)
        if (options.rungs[i] <= options.rungs[i - 1]) throw InputError("converge: the rungs must increase");
    if (options.samplers.empty()) throw InputError("converge: no samplers");
    if (options.seeds < 1) throw InputError("--seeds: expected at least 1");
    auto log = [&](const std::string& line) {
        if (options.log) options.log(line);
    };
    const int width = scene.film.width, height = scene.film.height;
    const uint32_t top = options.rungs.back();

    ConvergenceReport report;
    report.width = width;
    report.height = height;
    report.rungs = options.rungs;
    report.frozenDims = options.frozenDims;

    const int side = std::min({64, width, height});
    report.stripWindow = options.stripWindow.value_or(PixelWindow{
        (width - side) / 2, (width - side) / 2 + side, (height - side) / 2, (height - side) / 2 + side});
    const PixelWindow& sw = report.stripWindow;
    if (sw.x0 < 0 || sw.y0 < 0 || sw.x1 > width || sw.y1 > height || sw.width() <= 0 || sw.height() <= 0)
        throw InputError(fmt::format("--strip: the window {},{},{},{} must lie inside the {}x{} image", sw.x0,
                                     sw.x1, sw.y0, sw.y1, width, height));

    RenderOptions base;
    base.threads = options.threads;
    base.accelerator = options.accelerator;
    base.frozenDims = options.frozenDims;

    if (options.referencePath) {
        loadReference(*options.referencePath, width, height, report);
        log(fmt::format("reference: {}", options.referencePath->string()));
    } else {
        Scene refScene = scene;
        refScene.film.adaptive.reset();  // the reference and the ladder sample every pixel alike
        refScene.settings.sampler = SamplerKind::Stratified;
        refScene.integrator.strategy = LightStrategy::Mis;
        refScene.settings.seed = mix64(scene.settings.seed ^ 0x7265666572656e63ull);  // not a study seed
        const uint32_t spp = options.referenceSpp
                                 ? options.referenceSpp
                                 : std::max(top, std::min(8 * top, ConvergenceOptions::kMaxReferenceSpp));
        log(fmt::format("rendering the reference: {}x{}, {} spp (stratified, seed {})", width, height, spp,
                        refScene.settings.seed));
        RenderOptions o = base;
        o.endSample = spp;
        RenderJob job(refScene, options.source, o);
        const RenderStats stats = job.run();
        const Film& film = job.film();
        report.referenceSource = "rendered";
        report.referenceSpp = spp;
        report.referenceSeed = refScene.settings.seed;
        report.referenceSeconds = stats.renderSeconds;
        report.reference = film.meanRgb();
        double floor = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const Rgb v = film.at(x, y).varianceOfMean();
                floor += double(v.r) + v.g + v.b;
            }
        report.referenceMseFloor = floor / double(report.reference.size());
        report.referenceFilm = FilmFile{std::move(job.film()), job.metadata()};
        log(fmt::format("  {:.2f} s", stats.renderSeconds));
    }

    // Every sampler with every strategy, in that order.
    const std::vector<LightStrategy> strategies = options.strategies.empty()
                                                      ? std::vector<LightStrategy>{scene.integrator.strategy}
                                                      : options.strategies;
    std::vector<std::pair<SamplerKind, LightStrategy>> combinations;
    for (SamplerKind sampler : options.samplers)
        for (LightStrategy strategy : strategies) combinations.emplace_back(sampler, strategy);
    for (const auto& [sampler, strategy] : combinations) {
        SamplerStudy study;
        study.sampler = sampler;
        study.strategy = strategy;
        study.name = std::string(samplerKindName(sampler));
        if (!options.strategies.empty()) study.name += " " + std::string(lightStrategyName(strategy));
        for (int k = 0; k < options.seeds; ++k) {
            Scene s = scene;
            s.film.adaptive.reset();
            s.settings.sampler = sampler;
            s.settings.seed = scene.settings.seed + uint64_t(k);
            s.integrator.strategy = strategy;
            SeedRun run;
            run.seed = s.settings.seed;
            RenderOptions o = base;
            o.endSample = top;
            o.passEnds = options.rungs;  // a pass boundary at every rung, where the film is measured
            RenderJob job(s, options.source, o);
            const Film& film = job.film();
            size_t next = 0;
            Clock::duration snapshots{};
            const auto start = Clock::now();
            auto atRung = [&](uint32_t end) {
                if (next >= options.rungs.size() || end != options.rungs[next]) return;
                const auto t0 = Clock::now();
                RungError e = measure(film, report.reference);
                e.spp = end;
                e.seconds = secondsOf(t0 - start - snapshots);
                run.rungs.push_back(e);
                if (k == 0) {
                    std::vector<float> crop;
                    crop.reserve(size_t(sw.width()) * sw.height() * 3);
                    for (int y = sw.y0; y < sw.y1; ++y)
                        for (int x = sw.x0; x < sw.x1; ++x) {
                            const Rgb m = film.at(x, y).mean();
                            crop.insert(crop.end(), {m.r, m.g, m.b});
                        }
                    study.strip.push_back(std::move(crop));
                    if (options.adaptive)
                        study.adaptiveThresholds.push_back(options.adaptiveError == AdaptiveError::Absolute
                                                               ? float(e.rmse)
                                                               : medianRelativeError(film));
                }
                ++next;
                snapshots += Clock::now() - t0;
            };
            const RenderStats stats = job.run(atRung);
            // Rung times count tracing only: leave out the acceleration structure's build.
            for (RungError& e : run.rungs) e.seconds = std::max(0.0, e.seconds - stats.buildSeconds);
            std::vector<double> spp, mse;
            for (const RungError& e : run.rungs) {
                spp.push_back(e.spp);
                mse.push_back(e.mse);
            }
            run.slope = logLogSlope(spp, mse);
            log(fmt::format("{} seed {}: RMSE {:.5g} at {} spp after {:.2f} s, slope {:.3f}", study.name,
                            run.seed, run.rungs.back().rmse, top, run.rungs.back().seconds, run.slope));
            study.runs.push_back(std::move(run));
        }
        std::vector<double> spp, meanMse, slopes;
        for (const SeedRun& run : study.runs) slopes.push_back(run.slope);
        for (size_t r = 0; r < options.rungs.size(); ++r) {
            std::vector<double> mse, rel, rmse, sec;
            for (const SeedRun& run : study.runs) {
                mse.push_back(run.rungs[r].mse);
                rel.push_back(run.rungs[r].relMse);
                rmse.push_back(run.rungs[r].rmse);
                sec.push_back(run.rungs[r].seconds);
            }
            RungError m;
            m.spp = options.rungs[r];
            m.mse = meanOf(mse);
            m.relMse = meanOf(rel);
            m.rmse = meanOf(rmse);
            m.seconds = meanOf(sec);
            study.mean.push_back(m);
            study.mseStd.push_back(stdOf(mse));
            study.relMseStd.push_back(stdOf(rel));
            spp.push_back(m.spp);
            meanMse.push_back(m.mse);
        }
        study.slope = logLogSlope(spp, meanMse);
        study.slopeStd = stdOf(slopes);
        if (options.adaptive) {
            Scene s = scene;
            s.settings.sampler = sampler;
            s.integrator.strategy = strategy;
            log(fmt::format("{} adaptive, seed {}, up to {} spp:", study.name, s.settings.seed,
                            top * kAdaptiveMaxSppFactor));
            AdaptiveStudy adaptive;
            adaptive.minSamples = options.adaptiveMinSamples;
            adaptive.error = options.adaptiveError;
            adaptive.runs = runAdaptiveRenders(
                s, base, options.rungs, study.adaptiveThresholds, options.adaptiveMinSamples,
                top * kAdaptiveMaxSppFactor,
                [&](const Film& film) {
                    const RungError e = measure(film, report.reference);
                    return RungMeasure{e.mse, e.rmse};
                },
                log, options.adaptiveError);
            std::vector<double> rmse, seconds;
            for (const RungError& e : study.runs.front().rungs) {
                rmse.push_back(e.rmse);
                seconds.push_back(e.seconds);
            }
            adaptive.equalError =
                compareAtEqualError(options.rungs, rmse, seconds, double(width) * height, adaptive.runs);
            study.adaptive = std::move(adaptive);
        }
        report.studies.push_back(std::move(study));
    }
    return report;
}

void writeConvergenceReport(const ConvergenceReport& report, const std::string& sceneFile,
                            const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    SourceLocation where;
    where.file = dir.string();
    if (ec) throw InputError(where, fmt::format("cannot create the output folder: {}", ec.message()));

    // CSV: one row per sampler, seed and rung.
    {
        std::string csv = "sampler,strategy,seed,spp,mse,rel_mse,rmse,seconds\n";
        for (const SamplerStudy& study : report.studies)
            for (const SeedRun& run : study.runs)
                for (const RungError& e : run.rungs)
                    csv += fmt::format("{},{},{},{},{:.9g},{:.9g},{:.9g},{:.6f}\n",
                                       samplerKindName(study.sampler), lightStrategyName(study.strategy),
                                       run.seed, e.spp, e.mse, e.relMse, e.rmse, e.seconds);
        writeTextFileAtomically(dir / "convergence.csv", "convergence table", csv);
    }

    using nlohmann::json;
    json j;
    j["scene"] = sceneFile;
    j["resolution"] = {report.width, report.height};
    j["rungs"] = report.rungs;
    j["frozen"] = frozenDimsName(report.frozenDims);
    j["reference"] = {{"source", report.referenceSource},
                      {"spp", report.referenceSpp},
                      {"seed", std::to_string(report.referenceSeed)},
                      {"seconds", report.referenceSeconds},
                      {"mse_floor", report.referenceMseFloor}};
    j["samplers"] = json::array();
    for (const SamplerStudy& study : report.studies) {
        json s;
        s["name"] = study.name;
        s["sampler"] = std::string(samplerKindName(study.sampler));
        s["strategy"] = std::string(lightStrategyName(study.strategy));
        s["slope"] = study.slope;
        s["slope_std"] = study.slopeStd;
        s["rungs"] = json::array();
        for (size_t r = 0; r < study.mean.size(); ++r) {
            const RungError& e = study.mean[r];
            s["rungs"].push_back({{"spp", e.spp},
                                  {"mse", e.mse},
                                  {"mse_std", study.mseStd[r]},
                                  {"rel_mse", e.relMse},
                                  {"rel_mse_std", study.relMseStd[r]},
                                  {"rmse", e.rmse},
                                  {"seconds", e.seconds}});
        }
        if (study.adaptive) {
            json a;
            a["min_spp"] = study.adaptive->minSamples;
            a["error"] = std::string(adaptiveErrorName(study.adaptive->error));
            a["runs"] = json::array();
            for (const AdaptiveRun& run : study.adaptive->runs)
                a["runs"].push_back({{"rung", run.rung},
                                     {"threshold", run.threshold},
                                     {"max_spp", run.maxSpp},
                                     {"mse", run.mse},
                                     {"rmse", run.rmse},
                                     {"seconds", run.seconds},
                                     {"samples", run.samples},
                                     {"mean_spp", run.meanSpp}});
            // NaN (no adaptive run at that error) is written as null.
            auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
            a["equal_error"] = json::array();
            for (const EqualErrorPoint& p : study.adaptive->equalError)
                a["equal_error"].push_back({{"spp", p.spp},
                                            {"rmse", p.rmse},
                                            {"fixed_seconds", p.fixedSeconds},
                                            {"adaptive_seconds", number(p.adaptiveSeconds)},
                                            {"time_ratio", number(p.adaptiveSeconds / p.fixedSeconds)},
                                            {"fixed_samples", p.fixedSamples},
                                            {"adaptive_samples", number(p.adaptiveSamples)},
                                            {"sample_ratio", number(p.adaptiveSamples / p.fixedSamples)}});
            s["adaptive"] = a;
        }
        s["runs"] = json::array();
        for (const SeedRun& run : study.runs) {
            json rj;
            rj["seed"] = std::to_string(run.seed);
            rj["slope"] = run.slope;
            rj["mse"] = json::array();
            rj["seconds"] = json::array();
            for (const RungError& e : run.rungs) {
                rj["mse"].push_back(e.mse);
                rj["seconds"].push_back(e.seconds);
            }
            s["runs"].push_back(rj);
        }
        j["samplers"].push_back(s);
    }
    const PixelWindow& sw = report.stripWindow;
    j["strip"] = {{"file", "strip.png"},
                  {"window", {sw.x0, sw.x1, sw.y0, sw.y1}},
                  {"rows", json::array()},
                  {"columns", report.rungs}};
    for (const SamplerStudy& study : report.studies) j["strip"]["rows"].push_back(study.name);
    j["strip"]["columns"].push_back("reference");
    writeTextFileAtomically(dir / "convergence.json", "convergence report", j.dump(2) + "\n");

    // The strip: the same crop at each rung (columns) for each sampler (rows), the reference last;
    // small crops are enlarged (nearest neighbour) so that the noise can be seen.
    const int scale = std::max(1, 128 / std::max(sw.width(), sw.height()));
    const int tileW = sw.width() * scale, tileH = sw.height() * scale, gap = 2;
    const int columns = int(report.rungs.size()) + 1, rows = std::max<int>(1, int(report.studies.size()));
    Film strip(columns * tileW + (columns - 1) * gap, rows * tileH + (rows - 1) * gap);
    auto paint = [&](int row, int column, const std::vector<float>& rgb, bool fullImage) {
        for (int y = 0; y < tileH; ++y)
            for (int x = 0; x < tileW; ++x) {
                const int sx = x / scale, sy = y / scale;
                const size_t i = fullImage ? (size_t(sw.y0 + sy) * report.width + sw.x0 + sx) * 3
                                           : (size_t(sy) * sw.width() + sx) * 3;
                strip.add(column * (tileW + gap) + x, row * (tileH + gap) + y,
                          Rgb(rgb[i], rgb[i + 1], rgb[i + 2]), 1.0f);
            }
    };
    for (int row = 0; row < int(report.studies.size()); ++row) {
        const SamplerStudy& study = report.studies[row];
        for (int c = 0; c < int(study.strip.size()); ++c) paint(row, c, study.strip[c], false);
        paint(row, columns - 1, report.reference, true);
    }
    writeDisplayImage(strip, dir / "strip.png");
}

int runConvergeCommand(const ConvergeCommand& cmd) {
    SceneFileOptions sceneOptions;
    sceneOptions.patch = cmd.patch;
    Scene scene = loadSceneFile(cmd.scenePath, sceneOptions);
    if (!cmd.resolution.empty()) {
        const auto parts = splitText(cmd.resolution, 'x');
        if (parts.size() != 2)
            throw InputError(fmt::format("--res: expected WIDTHxHEIGHT, got '{}'", cmd.resolution));
        scene.film.width = int(parseIntegerOption("--res", parts[0], 1, limits::kMaxImageSide));
        scene.film.height = int(parseIntegerOption("--res", parts[1], 1, limits::kMaxImageSide));
    }
    if (cmd.seed) scene.settings.seed = *cmd.seed;
    if (cmd.output.empty()) throw InputError("converge: -o DIR is required");

    ConvergenceOptions options;
    options.rungs = parseRungs(cmd.spp);
    options.samplers.clear();
    for (const std::string& name : splitText(cmd.samplers, ',')) {
        if (name == "stratified")
            options.samplers.push_back(SamplerKind::Stratified);
        else if (name == "independent")
            options.samplers.push_back(SamplerKind::Independent);
        else
            throw InputError(
                fmt::format("--sampler: expected stratified and/or independent, got '{}'", name));
    }
    if (!cmd.strategies.empty())
        for (const std::string& name : splitText(cmd.strategies, ',')) {
            const LightStrategy all[] = {LightStrategy::Mis, LightStrategy::Bsdf, LightStrategy::Light};
            const auto found = std::find_if(std::begin(all), std::end(all),
                                            [&](LightStrategy s) { return lightStrategyName(s) == name; });
            if (found == std::end(all))
                throw InputError(fmt::format("--strategy: expected mis, bsdf and/or light, got '{}'", name));
            options.strategies.push_back(*found);
        }
    if (cmd.seeds < 1 || cmd.seeds > 1000)
        throw InputError(fmt::format("--seeds: expected 1 to 1000, got {}", cmd.seeds));
    options.seeds = cmd.seeds;
    options.frozenDims = parseFrozenDims(cmd.freeze);
    if (!cmd.reference.empty() && cmd.referenceSpp)
        throw InputError("converge: give either --reference or --reference-spp, not both");
    if (!cmd.reference.empty()) options.referencePath = cmd.reference;
    if (cmd.referenceSpp) {
        if (*cmd.referenceSpp < 1) throw InputError("--reference-spp: expected a positive integer");
        options.referenceSpp = *cmd.referenceSpp;
    }
    if (!cmd.strip.empty()) {
        const auto parts = splitText(cmd.strip, ',');
        if (parts.size() != 4)
            throw InputError(fmt::format("--strip: expected x0,x1,y0,y1, got '{}'", cmd.strip));
        options.stripWindow = PixelWindow{int(parseIntegerOption("--strip", parts[0], 0, 1 << 16)),
                                          int(parseIntegerOption("--strip", parts[1], 0, 1 << 16)),
                                          int(parseIntegerOption("--strip", parts[2], 0, 1 << 16)),
                                          int(parseIntegerOption("--strip", parts[3], 0, 1 << 16))};
    }
    options.threads = cmd.threads;
    options.accelerator = cmd.accel == "bvh" ? AcceleratorKind::Bvh : AcceleratorKind::Embree;
    if (!cmd.quiet)
        options.log = [](const std::string& line) {
            std::printf("%s\n", line.c_str());
            std::fflush(stdout);
        };
    options.source = SceneSource::of(cmd.scenePath, scene);
    if (cmd.minSpp && !cmd.adaptive) throw InputError("--min-spp: only with --adaptive");
    if (!cmd.adaptiveError.empty() && !cmd.adaptive)
        throw InputError("--adaptive-error: only with --adaptive");
    const std::optional<AdaptiveError> adaptiveError =
        cmd.adaptiveError.empty() ? AdaptiveError::Relative : parseAdaptiveError(cmd.adaptiveError);
    if (!adaptiveError)
        throw InputError(
            fmt::format("--adaptive-error: expected relative or absolute, got '{}'", cmd.adaptiveError));
    options.adaptive = cmd.adaptive;
    options.adaptiveError = *adaptiveError;
    if (cmd.minSpp) {
        if (*cmd.minSpp < AdaptiveSettings::kMinMinSamples || *cmd.minSpp > (1 << 24))
            throw InputError(fmt::format("--min-spp: expected an integer in [{}, {}], got {}",
                                         AdaptiveSettings::kMinMinSamples, 1 << 24, *cmd.minSpp));
        options.adaptiveMinSamples = uint32_t(*cmd.minSpp);
    }

    const ConvergenceReport report = runConvergence(scene, options);
    const std::filesystem::path dir(cmd.output);
    writeConvergenceReport(report, cmd.scenePath, dir);
    if (report.referenceFilm)
        writeExr(report.referenceFilm->film, report.referenceFilm->metadata, dir / "reference.exr");

    if (!cmd.noPlot) {
        const std::string python =
            std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
        const std::vector<std::string> command = {python, sharedDataPath("plot_convergence.py").string(),
                                                  (dir / "convergence.json").string(),
                                                  (dir / "convergence.png").string()};
        const ProgramResult plot = runProgram(command);
        if (plot.exitStatus != 0)
            std::fprintf(
                stderr,
                "penumbra: warning: the plot was not made (needs python3 with matplotlib): %s\nrun: %s\n",
                plot.output.c_str(), commandLineFor(command).c_str());
    }
    if (!cmd.quiet) {
        std::printf("%-18s %8s %10s %12s %10s\n", "sampler", "slope", "spp", "RMSE", "seconds");
        for (const SamplerStudy& s : report.studies)
            std::printf("%-18s %8.3f %10u %12.5g %10.2f\n", s.name.c_str(), s.slope, s.mean.back().spp,
                        s.mean.back().rmse, s.mean.back().seconds);
        for (const SamplerStudy& s : report.studies) {
            if (!s.adaptive) continue;
            std::printf("%s: adaptive against fixed at equal RMSE (seed %s)\n", s.name.c_str(),
                        std::to_string(s.runs.front().seed).c_str());
            std::printf("%8s %12s %10s %10s %8s %14s %14s %8s\n", "spp", "RMSE", "fixed s", "adapt. s",
                        "time", "fixed samples", "adapt. samples", "samples");
            for (const EqualErrorPoint& p : s.adaptive->equalError) {
                if (!std::isfinite(p.adaptiveSeconds)) {
                    std::printf("%8u %12.5g %10.2f %10s %8s %14.0f %14s %8s\n", p.spp, p.rmse, p.fixedSeconds,
                                "-", "-", p.fixedSamples, "-", "-");
                    continue;
                }
                std::printf("%8u %12.5g %10.2f %10.2f %7.2fx %14.0f %14.0f %7.2fx\n", p.spp, p.rmse,
                            p.fixedSeconds, p.adaptiveSeconds, p.adaptiveSeconds / p.fixedSeconds,
                            p.fixedSamples, p.adaptiveSamples, p.adaptiveSamples / p.fixedSamples);
            }
        }
        std::printf("wrote %s\n", dir.string().c_str());
    }
    return 0;
}

}  // namespace penumbra
