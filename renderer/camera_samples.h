// The camera ray of one sample, as the render loop draws it. Shared by renderer/render.cpp and
// the benchmark that replays the render's paths (bench/ray_throughput.cpp), so that both trace
// the same rays.
#pragma once

#include "cameras/camera.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "scenes/scene.h"

namespace penumbra {

// Offset of a sample from the pixel centre, drawn from the reconstruction filter.
inline Vec2f sampleFilterOffset(const FilmSettings& film, Vec2f u) {
    switch (film.filter) {
        case FilterKind::Box:
            return {(2.0f * u.x - 1.0f) * film.filterRadius, (2.0f * u.y - 1.0f) * film.filterRadius};
        case FilterKind::Tent:
            return {sampleTent(u.x, film.filterRadius), sampleTent(u.y, film.filterRadius)};
    }
    return {0.0f, 0.0f};
}

// The ray of `sample` in pixel (x, y). Dimensions that nothing reads are not drawn: the lens
// sample for a pinhole camera, the time sample when nothing in the scene moves (`sceneMoves`,
// Scene::hasMotion()); the other dimensions do not depend on them. The time is stratified jointly
// with the position in the pixel (PixelSample::get1DJointWith).
inline CameraRay generateCameraRay(const Camera& camera, const FilmSettings& film, bool sceneMoves,
                                   const PixelSample& sample, int x, int y) {
    const Vec2f offset = sampleFilterOffset(film, sample.get2D(Dim::Pixel));
    const Vec2f filmPosition{float(x) + 0.5f + offset.x, float(y) + 0.5f + offset.y};
    const Vec2f lens = camera.usesLensSample() ? sample.get2D(Dim::Lens) : Vec2f{0.5f, 0.5f};
    const float time = sceneMoves ? sample.get1DJointWith(Dim::Pixel, Dim::Time) : 0.5f;
    return camera.generateRay(filmPosition, lens, time);
}

}  // namespace penumbra
