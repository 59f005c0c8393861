// A render's mean of one channel over its pixels, with the mean's standard error from the pixels'
// spread: for tests whose every pixel estimates the same value independently of the others (a
// narrow field of view, or a value the same everywhere).
#pragma once

#include <cmath>
#include <vector>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene.h"

namespace penumbra::testing {

struct PixelMean {
    double mean, standardError;
};

inline PixelMean renderedChannelMean(const Scene& scene, int channel,
                                     AcceleratorKind accelerator = AcceleratorKind::Embree) {
    Film film(scene.film.width, scene.film.height);
    RenderOptions options;
    options.accelerator = accelerator;
    render(scene, options, film);
    std::vector<double> values;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            values.push_back(film.at(x, y).radiance[channel] / film.at(x, y).weight);
    double sum = 0, sumSquares = 0;
    for (double v : values) sum += v;
    const double mean = sum / double(values.size());
    for (double v : values) sumSquares += (v - mean) * (v - mean);
    const double variance = sumSquares / double(values.size() - 1);
    return {mean, std::sqrt(variance / double(values.size()))};
}

}  // namespace penumbra::testing
