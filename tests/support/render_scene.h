// A scene rendered into a film of its own size, on `threads` threads (0: all) with a chosen backend:
// what the tests that compare renders (two backends, two thread counts, two scenes) all do.
#pragma once

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra::testing {

inline Film renderScene(const Scene& scene, int threads = 2,
                        AcceleratorKind accelerator = AcceleratorKind::Embree) {
    RenderOptions options;
    options.threads = threads;
    options.accelerator = accelerator;
    Film film(scene.film.width, scene.film.height);
    render(scene, options, film);
    return film;
}

}  // namespace penumbra::testing
