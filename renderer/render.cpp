#include "renderer/render.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "cameras/camera.h"
#include "core/error.h"
#include "core/input_limits.h"
#include "film/pixel_accumulator.h"
#include "renderer/adaptive_sampling.h"
#include "renderer/camera_samples.h"
#include "renderer/prepared_scene.h"
#include "renderer/render_tile.h"
#include "textures/image_texture.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;
using detail::kMaxNonFiniteExamples;
using detail::renderTile;
using detail::renderTileThroughMedia;
using detail::TileResult;

template <TraversalBackend Accel>
RenderStats renderWith(const Accel& accel, const Scene& scene, const RenderOptions& options, Film& film) {
    const PreparedScene prepared(scene);
    const Camera& camera = prepared.camera();
    const IntegratorContext ctx = prepared.integratorContext();
    const bool sceneMoves = prepared.moves();  // otherwise no time sample is drawn
    const bool throughMedia = scene.hasMedia();
    const PixelWindow window = options.crop.value_or(PixelWindow{0, scene.film.width, 0, scene.film.height});
    const uint32_t endSample = options.endSample ? options.endSample : uint32_t(scene.film.samplesPerPixel);
    const int tileSize = std::max(1, options.tileSize);
    std::vector<PixelWindow> tiles;
    for (int y = window.y0; y < window.y1; y += tileSize)
        for (int x = window.x0; x < window.x1; x += tileSize)
            tiles.push_back({x, std::min(x + tileSize, window.x1), y, std::min(y + tileSize, window.y1)});

    // Passes of sample indices (one pass unless options.passSize or passEnds say otherwise): every
    // pass renders all tiles, so between passes every pixel holds the same samples. A pass ends at
    // the next multiple of the pass size, like the packets' groups of sample indices, so that a
    // resume from any index keeps the packets of later passes whole, or at options.passEnds.
    const uint32_t firstSample = std::min(options.firstSample, endSample);
    // Adaptive sampling: a pass also ends at each of its decision points, where pixels stop. The
    // pixels active at firstSample are those that hold all its samples (a resumed film's stopped
    // pixels hold fewer); if firstSample is a decision point, it is taken again here, from the
    // same film, as the render that wrote the film took it.
    const std::optional<AdaptiveSettings>& adaptive = scene.film.adaptive;
    std::optional<ActivePixels> active;
    if (adaptive) {
        active.emplace(film, window, firstSample);
        if (adaptive->isDecisionPoint(firstSample) && firstSample < endSample)
            active->stopConverged(film, *adaptive);
    }
    auto passEndAfter = [&](uint32_t begin) {
        uint64_t end = endSample;
        if (adaptive) end = std::min<uint64_t>(end, adaptive->nextDecisionAfter(begin));
        if (options.passSize > 0)
            end = std::min<uint64_t>(end, (uint64_t(begin) / options.passSize + 1) * options.passSize);
        for (const uint32_t boundary : options.passEnds)
            if (boundary > begin && boundary < end) end = boundary;
        return uint32_t(end);
    };
    size_t passes = 0;
    for (uint32_t begin = firstSample; begin < endSample; begin = passEndAfter(begin)) ++passes;
    const size_t totalTiles = tiles.size() * passes;

    std::vector<TileResult> results(tiles.size());
    std::atomic<size_t> tilesDone{0};
    std::mutex progressMutex;
    const auto start = Clock::now();
    Clock::duration callbackTime{};
    uint32_t passBegin = firstSample, passEnd = firstSample;
    auto renderRange = [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
            const ActivePixels* activePixels = active ? &*active : nullptr;
            TileResult r =
                throughMedia ? renderTileThroughMedia(accel, scene, camera, ctx, tiles[i], passBegin, passEnd,
                                                      options.frozenDims, sceneMoves, activePixels, film)
                             : renderTile<false>(accel, scene, camera, ctx, tiles[i], passBegin, passEnd,
                                                 options.frozenDims, sceneMoves, activePixels, film);
            TileResult& total = results[i];
            total.rays += r.rays;
            total.samples += r.samples;
            total.nonFinite += r.nonFinite;
            for (const auto& e : r.examples)
                if (total.examples.size() < kMaxNonFiniteExamples) total.examples.push_back(e);
            const size_t done = ++tilesDone;
            if (options.progress) {
                std::lock_guard lock(progressMutex);
                options.progress(done, totalTiles);
            }
        }
    };
    if (options.threads < 0 || options.threads > limits::kMaxThreads)
        throw InputError(fmt::format("threads: expected 0 (every core) to {}, got {}", limits::kMaxThreads,
                                     options.threads));
    const int threads = renderThreads(options.threads);
    tbb::task_arena arena(threads);
    RenderStats stats;
    stats.endSample = firstSample;
    for (passBegin = firstSample; passBegin < endSample; passBegin = passEnd) {
        if (options.cancel && options.cancel->load()) {
            stats.cancelled = true;
            break;
        }
        if (active && active->count() == 0) {
            // Every pixel has stopped: the film is the one a render to endSample ends with.
            stats.endSample = endSample;
            break;
        }
        passEnd = passEndAfter(passBegin);
        arena.execute(
            [&] { tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), renderRange); });
        // A texture that could not be read stops the render before this pass reaches the film's
        // checkpoints or output.
        throwIfTextureLookupsFailed();
        stats.endSample = passEnd;
        if (active && adaptive->isDecisionPoint(passEnd) && passEnd < endSample)
            active->stopConverged(film, *adaptive);
        if (options.passDone) {
            const auto callbackStart = Clock::now();
            options.passDone(passEnd);
            callbackTime += Clock::now() - callbackStart;
        }
    }

    stats.renderSeconds = std::chrono::duration<double>(Clock::now() - start - callbackTime).count();
    // Tiles are merged in their fixed order, so the reported examples do not depend on scheduling.
    for (const TileResult& r : results) {
        stats.rays += r.rays;
        stats.samples += r.samples;
        stats.nonFiniteCount += r.nonFinite;
        for (const auto& e : r.examples)
            if (stats.nonFiniteExamples.size() < kMaxNonFiniteExamples) stats.nonFiniteExamples.push_back(e);
    }
    return stats;
}

}  // namespace

int renderThreads(int requested) {
    return requested > 0 ? requested : tbb::this_task_arena::max_concurrency();
}

uint32_t defaultPassSize(uint64_t windowPixels) {
    constexpr uint64_t kAlignment = EmbreeAccelerator::kPacketSize;
    const uint64_t samples = std::max<uint64_t>(1, (uint64_t(1) << 20) / std::max<uint64_t>(1, windowPixels));
    return uint32_t(
        std::min<uint64_t>((samples + kAlignment - 1) / kAlignment * kAlignment, uint64_t(1) << 20));
}

PixelWindow cropWindowPixels(const std::array<float, 4>& window, int width, int height) {
    // In float, as pbrt-v4 computes it: 20 x 0.2f is 4 in float, 4.00000006 in double.
    auto edge = [](float fraction, int size) { return int(std::ceil(float(size) * fraction)); };
    const PixelWindow pixels{edge(window[0], width), edge(window[1], width), edge(window[2], height),
                             edge(window[3], height)};
    if (pixels.width() <= 0 || pixels.height() <= 0)
        throw InputError(fmt::format("film.crop_window [{}, {}, {}, {}] holds no pixel of the {}x{} image",
                                     window[0], window[1], window[2], window[3], width, height));
    return pixels;
}

RenderStats render(const Scene& scene, const RenderOptions& options, Film& film) {
    if (film.width() != scene.film.width || film.height() != scene.film.height)
        throw InputError("render: the film's size does not match the scene's resolution");
    if (options.crop) {
        const PixelWindow& c = *options.crop;
        if (c.x0 < 0 || c.y0 < 0 || c.x1 > scene.film.width || c.y1 > scene.film.height || c.x0 >= c.x1 ||
            c.y0 >= c.y1)
            throw InputError("--crop: the window must lie inside the image and not be empty");
    }
    const auto buildStart = Clock::now();
    switch (options.accelerator) {
        case AcceleratorKind::Embree: {
            const EmbreeAccelerator accel(scene, EmbreeOptions{.robust = scene.settings.watertight});
            const double buildSeconds = std::chrono::duration<double>(Clock::now() - buildStart).count();
            RenderStats stats = renderWith(accel, scene, options, film);
            stats.buildSeconds = buildSeconds;
            return stats;
        }
        case AcceleratorKind::Bvh: {
            const BvhAccelerator accel(scene);
            const double buildSeconds = std::chrono::duration<double>(Clock::now() - buildStart).count();
            RenderStats stats = renderWith(accel, scene, options, film);
            stats.buildSeconds = buildSeconds;
            return stats;
        }
    }
    throw InputError("render: unknown accelerator");
}

}  // namespace penumbra
