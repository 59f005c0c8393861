#include "tools/adaptive_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/adaptive_sampling.h"
#include "renderer/render_job.h"

namespace penumbra {

namespace {

// log(y) at log(x) = log(at), linear between the two points of (x, y), sorted by x, around it;
// NaN outside their range.
double interpolateLogLog(const std::vector<std::pair<double, double>>& points, double at) {
    for (size_t i = 1; i < points.size(); ++i) {
        const auto [x0, y0] = points[i - 1];
        const auto [x1, y1] = points[i];
        if (at < x0 || at > x1 || !(x0 > 0 && x1 > 0 && y0 > 0 && y1 > 0)) continue;
        if (x1 == x0) return y0;
        const double t = (std::log(at) - std::log(x0)) / (std::log(x1) - std::log(x0));
        return std::exp(std::log(y0) + t * (std::log(y1) - std::log(y0)));
    }
    return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

float medianRelativeError(const Film& film) {
    std::vector<double> errors;
    errors.reserve(size_t(film.width()) * film.height());
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            if (film.at(x, y).sampleCount >= 2) errors.push_back(relativeStandardError(film.at(x, y)));
    if (errors.empty()) return 0.0f;
    const auto middle = errors.begin() + std::ptrdiff_t(errors.size() / 2);
    std::nth_element(errors.begin(), middle, errors.end());
    return float(*middle);
}

std::vector<AdaptiveRun> runAdaptiveRenders(const Scene& scene, const RenderOptions& base,
                                            const std::vector<uint32_t>& rungs,
                                            const std::vector<float>& thresholds, uint32_t minSamples,
                                            uint32_t maxSpp,
                                            const std::function<RungMeasure(const Film&)>& measure,
                                            const std::function<void(const std::string&)>& log,
                                            AdaptiveError error) {
    std::vector<AdaptiveRun> runs;
    for (size_t i = 0; i < rungs.size(); ++i) {
        if (rungs[i] < minSamples || !(thresholds[i] > 0.0f)) continue;
        Scene s = scene;
        s.film.adaptive = AdaptiveSettings{std::min(thresholds[i], AdaptiveSettings::maxThreshold(error)),
                                           minSamples, error};
        RenderOptions o = base;
        o.endSample = maxSpp;
        RenderJob job(s, SceneSource{}, o);
        const RenderStats stats = job.run();
        const RungMeasure error = measure(job.film());
        AdaptiveRun run;
        run.rung = rungs[i];
        run.threshold = s.film.adaptive->threshold;
        run.maxSpp = maxSpp;
        run.mse = error.mse;
        run.rmse = error.rmse;
        run.seconds = stats.renderSeconds;
        run.samples = stats.samples;
        run.meanSpp = double(stats.samples) / (double(scene.film.width) * scene.film.height);
        if (log)
            log(fmt::format("  adaptive {:.4g} (rung {}): RMSE {:.5g}, {:.1f} spp on average, {:.2f} s",
                            run.threshold, run.rung, run.rmse, run.meanSpp, run.seconds));
        runs.push_back(run);
    }
    return runs;
}

std::vector<EqualErrorPoint> compareAtEqualError(const std::vector<uint32_t>& spp,
                                                 const std::vector<double>& rmse,
                                                 const std::vector<double>& seconds, double pixels,
                                                 const std::vector<AdaptiveRun>& runs) {
    std::vector<std::pair<double, double>> byTime, bySamples;  // (RMSE, y), sorted by RMSE
    for (const AdaptiveRun& run : runs) {
        byTime.emplace_back(run.rmse, run.seconds);
        bySamples.emplace_back(run.rmse, double(run.samples));
    }
    std::sort(byTime.begin(), byTime.end());
    std::sort(bySamples.begin(), bySamples.end());
    std::vector<EqualErrorPoint> points;
    for (size_t i = 0; i < spp.size(); ++i) {
        EqualErrorPoint p;
        p.spp = spp[i];
        p.rmse = rmse[i];
        p.fixedSeconds = seconds[i];
        p.fixedSamples = double(spp[i]) * pixels;
        p.adaptiveSeconds = interpolateLogLog(byTime, rmse[i]);
        p.adaptiveSamples = interpolateLogLog(bySamples, rmse[i]);
        points.push_back(p);
    }
    return points;
}

}  // namespace penumbra
