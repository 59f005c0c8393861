// The render loop: the image is cut into tiles that TBB renders in parallel. Every sample value
// is a function of (seed, pixel, sample index, dimension) and every sample only touches its own
// pixel, so the film is bit-identical whatever the thread count or the order tiles finish in.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "accel/traversal.h"
#include "film/film.h"
#include "renderer/path_integrator.h"
#include "scenes/scene.h"

namespace penumbra {

// PixelWindow ([x0, x1) x [y0, y1)) is declared in film/film.h.

struct RenderOptions {
    AcceleratorKind accelerator = AcceleratorKind::Embree;
    int threads = 0;                  // 0: all cores
    uint32_t firstSample = 0;         // render sample indices [firstSample, endSample)
    uint32_t endSample = 0;           // 0: the scene's samples per pixel
    std::optional<PixelWindow> crop;  // only these pixels
    int tileSize = 16;
    // Called with (tiles done, tiles in all) as tiles finish, from whichever thread finished one.
    std::function<void(size_t, size_t)> progress;
    // Passes: with passSize k > 0 every pixel of the window gets samples [a, a + k) before any
    // pixel gets sample a + k, so at each pass boundary every pixel has the same samples
    // [firstSample, passEnd). Passes end at multiples of k (the first may be shorter when
    // firstSample is not one). 0: one pass (each tile renders all its samples). The film is the
    // same bit for bit either way (see ExactSum in film.h).
    uint32_t passSize = 0;
    // More pass boundaries, at these sample indices (convergence rungs): a pass also ends at each.
    std::vector<uint32_t> passEnds;
    // Called on the calling thread after each pass, with the film consistent at [firstSample,
    // passEnd): checkpoints and convergence snapshots are taken here.
    std::function<void(uint32_t passEnd)> passDone;
    // Checked before each pass: once it reads true no new pass starts (the current one is
    // finished, so the film stays consistent) and RenderStats::cancelled is set.
    const std::atomic<bool>* cancel = nullptr;
    // Sample dimensions frozen at their centre, a mask of PixelSample::dimBit(Dim) (convergence
    // studies: `penumbra converge --freeze`).
    uint32_t frozenDims = 0;
};

// The pixels of a scene's film.crop_window (fractions x0, x1, y0, y1) at a resolution, rounded as
// pbrt-v4 rounds its cropwindow (each bound up to the next pixel edge). Throws InputError when no
// pixel is left (a window narrower than a pixel).
PixelWindow cropWindowPixels(const std::array<float, 4>& window, int width, int height);

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
    // Every pixel of the window holds samples [firstSample, endSample); with adaptive sampling
    // (the scene's film.adaptive) each holds [0, k) for its own k <= endSample, and endSample
    // is reached early when every pixel has stopped.
    uint32_t endSample = 0;
    bool cancelled = false;  // stopped early through RenderOptions::cancel (endSample tells where)
    uint64_t nonFiniteCount = 0;
    std::vector<NonFiniteSample> nonFiniteExamples;  // the first few, in pixel order
};

// The pass size for about a million samples a pass over `windowPixels` pixels (a signal or a
// checkpoint then waits about that long), rounded up to a multiple of the camera-ray packet size:
// a pass that ends inside a packet's sample indices splits the packet in two half-empty ones
// (bench/README.md, "Speed tricks").
uint32_t defaultPassSize(uint64_t windowPixels);

// The worker threads a render with RenderOptions::threads = `requested` uses (0: every core the
// process may use).
int renderThreads(int requested);

// Renders `scene` into `film` (sized to the scene's resolution), adding to what it holds. With
// adaptive sampling (scene.film.adaptive, renderer/adaptive_sampling.h) the film must hold what an
// adaptive render of samples [0, options.firstSample) left in it (nothing when firstSample is 0):
// the pixels holding firstSample samples go on, the others have stopped.
RenderStats render(const Scene& scene, const RenderOptions& options, Film& film);

}  // namespace penumbra
