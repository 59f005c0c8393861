// One tile's samples through one of the two integrators: the render loop's body
// (renderer/render.cpp), shared by render.cpp (the surface integrator) and render_through_media.cpp
// (the volumetric one, kThroughMedia). Each integrator is instantiated in a translation unit of its
// own: in one, the surface integrator lost its inlining (GCC's growth limits for the unit; +3% of
// its instructions, bench/README.md).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "cameras/camera.h"
#include "film/film.h"
#include "film/pixel_accumulator.h"
#include "renderer/adaptive_sampling.h"
#include "renderer/camera_samples.h"
#include "renderer/path_integrator.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra {

// renderer/volumetric_path_integrator.h, which only render_through_media.cpp includes.
template <TraversalBackend Accel>
Radiance estimateRadianceThroughMedia(const Accel& accel, const IntegratorContext& ctx, Ray ray,
                                      const PixelSample& sample, RayCounters& rays, FirstHitAovs* firstHit);

namespace detail {

constexpr size_t kMaxNonFiniteExamples = 8;

struct TileResult {
    RayCounters rays;
    uint64_t samples = 0;
    uint64_t nonFinite = 0;
    std::vector<NonFiniteSample> examples;
};

// kThroughMedia: the volumetric integrator (Scene::hasMedia), whose camera rays are traced one
// at a time; otherwise the surface integrator, with camera rays traced as packets.
template <bool kThroughMedia, TraversalBackend Accel>
TileResult renderTile(const Accel& accel, const Scene& scene, const Camera& camera,
                      const IntegratorContext& ctx, const PixelWindow& tile, uint32_t firstSample,
                      uint32_t endSample, uint32_t frozenDims, bool sceneMoves, const ActivePixels* active,
                      Film& film) {
    constexpr int kPacket = kThroughMedia ? 1 : Accel::kPacketSize;
    TileResult result;
    // A group's samples, camera rays and what they hit, declared once per tile: every entry used
    // is assigned first, so they need no zeroing per group (bench/README.md, "Speed tricks").
    std::optional<PixelSample> samples[kPacket];  // made once, for the camera ray and the path
    Ray cameraRays[kPacket];
    float cameraWeights[kPacket];  // 0: the camera sees nothing along the ray (cameras/camera_ray.h)
    TracedRay traced[kPacket];
    Hit hits[kPacket];
    bool found[kPacket];
    const SensorResponse* sensor = scene.film.sensor ? &*scene.film.sensor : nullptr;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            if (active && !active->active(x, y)) continue;  // stopped by adaptive sampling
            PixelAccumulator pixel(film, x, y);  // adds the samples to the film when the pixel is done
            const uint64_t pixelIndex = uint64_t(y) * uint64_t(scene.film.width) + uint64_t(x);
            const PixelKey pixelKey = PixelKey::of(scene.settings.seed, pixelIndex);
            // A pixel's camera rays are traced in packets of sample indices aligned to multiples of
            // the packet size, so every sample's camera ray meets the same kernel in the same lane
            // whatever range [firstSample, endSample) is rendered (resumes and merges stay exact).
            for (uint32_t groupStart = firstSample; groupStart < endSample;) {
                const uint32_t groupEnd = std::min(endSample, (groupStart / kPacket + 1) * kPacket);
                const int count = int(groupEnd - groupStart);
                for (int i = 0; i < count; ++i) {
                    samples[i].emplace(scene.settings.sampler, pixelKey, groupStart + i);
                    samples[i]->freeze(frozenDims);
                    const CameraRay cameraRay =
                        generateCameraRay(camera, scene.film, sceneMoves, *samples[i], x, y);
                    cameraRays[i] = cameraRay.ray;
                    cameraWeights[i] = cameraRay.weight;
                }
                if constexpr (kPacket > 1) {
                    accel.intersectPacket(cameraRays, count, hits, found);
                    for (int i = 0; i < count; ++i) traced[i] = {found[i], hits[i]};
                }
                for (int i = 0; i < count; ++i) {
                    const uint32_t s = groupStart + i;
                    FirstHitAovs aovs;
                    Rgb radiance(0.0f);
                    if (cameraWeights[i] == 0.0f) {
                        // No light reaches the film along this ray: the sample counts, as black.
                    } else if constexpr (kThroughMedia)
                        radiance = estimateRadianceThroughMedia(accel, ctx, cameraRays[i], *samples[i],
                                                                result.rays, &aovs);
                    else
                        radiance = estimateRadiance(accel, ctx, cameraRays[i], *samples[i], result.rays,
                                                    &aovs, kPacket > 1 ? &traced[i] : nullptr);
                    if (!radiance.isFinite()) {
                        ++result.nonFinite;
                        if (result.examples.size() < kMaxNonFiniteExamples)
                            result.examples.push_back({x, y, s});
                        radiance = Rgb(0.0f);
                    }
                    if (cameraWeights[i] != 1.0f) radiance = radiance * cameraWeights[i];
                    if (sensor) radiance = sensor->apply(radiance);
                    pixel.add(radiance, 1.0f, aovs);
                    ++result.samples;
                }
                groupStart = groupEnd;
            }
        }
    return result;
}

// renderTile<true>, instantiated for both backends in render_through_media.cpp.
template <TraversalBackend Accel>
TileResult renderTileThroughMedia(const Accel& accel, const Scene& scene, const Camera& camera,
                                  const IntegratorContext& ctx, const PixelWindow& tile, uint32_t firstSample,
                                  uint32_t endSample, uint32_t frozenDims, bool sceneMoves,
                                  const ActivePixels* active, Film& film);

}  // namespace detail
}  // namespace penumbra
