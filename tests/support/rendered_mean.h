// The radiance a point of a horizontal surface sends up, as a render measures it: `base` rendered
// by a camera one unit straight above `target`, looking down with the scene's own film and field of
// view (a narrow one keeps the footprint small), the pixels' red mean.
#pragma once

#include "core/vec.h"
#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra::testing {

inline double renderedMeanAt(Vec3f target, const Scene& base) {
    Scene scene = base;
    scene.camera.lookFrom = target + Vec3f{0.0f, 1.0f, 0.0f};
    scene.camera.lookAt = target;
    scene.camera.up = {0.0f, 0.0f, -1.0f};
    Film film(scene.film.width, scene.film.height);
    render(scene, RenderOptions{}, film);
    double sum = 0, count = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            sum += film.at(x, y).radiance[0];
            count += film.at(x, y).weight;
        }
    return sum / count;
}

}  // namespace penumbra::testing
