// The radiance a point of a horizontal surface sends up, as a render measures it: `base` rendered
// by a camera one unit straight above `target`, looking down with the scene's own film and field of
// view (a narrow one keeps the footprint small), the pixels' red mean.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec.h"
#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra::testing {

// The film of `base` seen from one unit above `target`, looking down.
inline Film renderedFromAbove(Vec3f target, const Scene& base) {
    Scene scene = base;
    scene.camera.lookFrom = target + Vec3f{0.0f, 1.0f, 0.0f};
    scene.camera.lookAt = target;
    scene.camera.up = {0.0f, 0.0f, -1.0f};
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    return film;
}

// The red mean over all samples.
inline double renderedMeanAt(Vec3f target, const Scene& base) {
    const Film film = renderedFromAbove(target, base);
    double sum = 0, count = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const PixelSums pixel = film.at(x, y);
            sum += pixel.radiance[0];
            count += pixel.weight;
        }
    return sum / count;
}

struct MeanEstimate {
    double mean = 0.0, standardError = 0.0;
};

// The mean of the pixels' red means and its standard error from their spread (pixels are
// independent estimates where the filter is a box of one pixel).
inline MeanEstimate renderedMeanAndErrorAt(Vec3f target, const Scene& base) {
    const Film film = renderedFromAbove(target, base);
    double sum = 0.0, sumSquares = 0.0;
    const double n = double(film.width()) * film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const double value = film.at(x, y).mean().r;
            sum += value;
            sumSquares += value * value;
        }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(sumSquares / n - mean * mean, 0.0) / (n - 1.0))};
}

}  // namespace penumbra::testing
