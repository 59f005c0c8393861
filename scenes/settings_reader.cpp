#include "scenes/settings_reader.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "core/input_limits.h"

namespace penumbra {

namespace {

// Larger films are surely typos, and this keeps width * height far from overflowing.
constexpr int64_t kMaxResolution = limits::kMaxImageSide;
constexpr int64_t kMaxInt = std::numeric_limits<int32_t>::max();

}  // namespace

FilmSettings readFilm(const JsonValue& value) {
    const JsonObject object(value, {"resolution", "spp", "filter", "crop_window", "adaptive", "sensor"});
    FilmSettings film;
    if (auto v = object.get("sensor")) {
        // A physical camera's exposure (cameras/sensor_response.h): ISO, exposure time, white balance.
        const JsonObject sensor(*v, {"iso", "exposure_time", "white_balance"});
        const float iso = sensor.get("iso") ? sensor.get("iso")->numberAbove(0.0f) : 100.0f;
        const float time =
            sensor.get("exposure_time") ? sensor.get("exposure_time")->numberAbove(0.0f) : 1.0f;
        float kelvin = 0.0f;
        if (auto k = sensor.get("white_balance")) {
            kelvin = k->number();
            if (!(kelvin == 0.0f || (kelvin >= 1000.0f && kelvin <= 100000.0f)))
                k->failExpected("a colour temperature from 1000 to 100000 kelvin, or 0 for none");
        }
        film.sensor = SensorResponse::make(iso, time, kelvin);
        if (!std::isfinite(film.sensor->imagingRatio()))
            v->fail("exposure_time x iso / 100 must fit a 32-bit float");
    }
    if (auto v = object.get("resolution")) {
        if (!v->json().is_array() || v->json().size() != 2)
            v->failExpected("an array [width, height] of 2 integers");
        film.width = int(v->element(0).integer(1, kMaxResolution));
        film.height = int(v->element(1).integer(1, kMaxResolution));
    }
    if (auto v = object.get("spp")) film.samplesPerPixel = int(v->integer(1, kMaxInt));
    if (auto v = object.get("filter")) {
        const JsonObject filter(*v, {"type", "radius"});
        if (auto type = filter.get("type"))
            film.filter = type->choice({"box", "tent"}) == 0 ? FilterKind::Box : FilterKind::Tent;
        if (auto radius = filter.get("radius")) {
            film.filterRadius = radius->numberAbove(0.0f);
            if (film.filterRadius > limits::kMaxFilterRadius)
                radius->failExpected(
                    fmt::format("a radius > 0 and <= {:g} pixels", limits::kMaxFilterRadius));
        }
    }
    if (auto v = object.get("crop_window")) {
        if (!v->json().is_array() || v->json().size() != 4)
            v->failExpected("an array [x0, x1, y0, y1] of 4 fractions of the image");
        std::array<float, 4> window{};
        for (size_t i = 0; i < 4; ++i) window[i] = v->element(i).numberInRange(0.0f, 1.0f);
        if (!(window[0] < window[1] && window[2] < window[3]))
            v->failExpected("x0 < x1 and y0 < y1 (a window with an area)");
        film.cropWindow = window;
    }
    if (auto v = object.get("adaptive")) {
        const JsonObject adaptive(*v, {"threshold", "min_spp", "error"});
        AdaptiveSettings settings;
        if (auto error = adaptive.get("error"))
            settings.error = error->choice({"relative", "absolute"}) == 0 ? AdaptiveError::Relative
                                                                          : AdaptiveError::Absolute;
        const auto threshold = adaptive.get("threshold");
        if (!threshold)
            v->fail(
                "adaptive sampling needs a \"threshold\" (a relative standard error, e.g. 0.02, or with "
                "\"error\": \"absolute\" the image's RMSE, e.g. 0.01)");
        settings.threshold = threshold->numberAbove(0.0f);
        if (settings.threshold > AdaptiveSettings::maxThreshold(settings.error))
            threshold->failExpected(
                settings.error == AdaptiveError::Relative
                    ? fmt::format("a relative standard error > 0 and <= {:g}",
                                  AdaptiveSettings::kMaxThreshold)
                    : fmt::format("an RMSE > 0 and <= {:g}", AdaptiveSettings::kMaxAbsoluteThreshold));
        if (auto minSpp = adaptive.get("min_spp"))
            settings.minSamples = uint32_t(minSpp->integer(AdaptiveSettings::kMinMinSamples, kMaxInt));
        film.adaptive = settings;
    }
    return film;
}

IntegratorSettings readIntegrator(const JsonValue& value) {
    const JsonObject object(value, {"max_depth", "roulette_start", "strategy", "light_sampler"});
    IntegratorSettings integrator;
    // Bounded: in a closed lossless mirror a path never ends before max_depth (roulette keeps a
    // throughput of 1), so 2^31 bounces would run for days and never reach a pass end (SIGTERM).
    if (auto v = object.get("max_depth")) integrator.maxDepth = int(v->integer(0, limits::kMaxPathDepth));
    if (auto v = object.get("roulette_start"))
        integrator.rouletteStartDepth = int(v->integer(0, limits::kMaxPathDepth));
    if (auto v = object.get("strategy"))
        integrator.strategy = LightStrategy(v->choice({"mis", "bsdf", "light"}));
    if (auto v = object.get("light_sampler"))
        integrator.lightSampler = LightSampler(v->choice({"bvh", "power"}));
    return integrator;
}

RenderSettings readRender(const JsonValue& value) {
    const JsonObject object(value, {"sampler", "seed", "watertight", "canonical_hits"});
    RenderSettings settings;
    if (auto v = object.get("sampler"))
        settings.sampler = v->choice({"stratified", "independent"}) == 0 ? SamplerKind::Stratified
                                                                         : SamplerKind::Independent;
    if (auto v = object.get("seed")) settings.seed = v->unsignedInteger();
    if (auto v = object.get("watertight")) settings.watertight = v->boolean();
    if (auto v = object.get("canonical_hits")) settings.canonicalHits = v->boolean();
    return settings;
}

}  // namespace penumbra
