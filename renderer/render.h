// The render loop: the image is cut into tiles that TBB renders in parallel. Every sample value
// is a function of (seed, pixel, sample index, dimension) and every sample only touches its own
// pixel, so the film is bit-identical whatever the thread count or the order tiles finish in.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "renderer/film.h"
#include "renderer/path_integrator.h"
#include "scenes/accelerator.h"
#include "scenes/scene.h"

namespace penumbra {

struct PixelWindow {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
};

struct RenderOptions {
    AcceleratorKind accelerator = AcceleratorKind::Embree;
    int threads = 0;                 // 0: all cores
    uint32_t firstSample = 0;        // render sample indices [firstSample, endSample)
    uint32_t endSample = 0;          // 0: the scene's samples per pixel
    std::optional<PixelWindow> crop; // only these pixels
    int tileSize = 16;
    // Called with (tiles done, tiles in all) as tiles finish, from whichever thread finished one.
    std::function<void(size_t, size_t)> progress;
};

// A sample whose radiance was NaN or infinite; it was recorded as black. Re-run it with
// `penumbra render SCENE --crop x,x+1,y,y+1 --samples i:i+1`.
struct NonFiniteSample {
    int x = 0, y = 0;
    uint32_t sampleIndex = 0;
};

struct RenderStats {
    double buildSeconds = 0.0;   // acceleration structure build
    double renderSeconds = 0.0;  // tracing and shading
    uint64_t samples = 0;
    RayCounters rays;
    uint64_t nonFiniteCount = 0;
    std::vector<NonFiniteSample> nonFiniteExamples;  // the first few, in pixel order
};

// Renders `scene` into `film` (sized to the scene's resolution), adding to what it holds.
RenderStats render(const Scene& scene, const RenderOptions& options, Film& film);

}  // namespace penumbra
