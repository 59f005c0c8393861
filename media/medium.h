// The closed set of participating media (a std::variant, as materials and lights are), and free-
// flight sampling through one of them: delta tracking against piecewise-constant majorants
// (Woodcock et al. 1965; in the null-scattering form of Miller, Georgiev and Jarosz 2019, as
// pbrt-v4's SampleT_maj).
//
// Colour: coefficients are RGB, one value per channel; distances are sampled with one channel's
// majorant (the path's hero channel, chosen per path) and the integrator weighs the channels by
// their densities (spectral MIS), so a chromatic medium stays unbiased in every channel.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>

#include "core/check.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "media/cloud_medium.h"
#include "media/grid_medium.h"
#include "media/homogeneous_medium.h"
#include "media/rgb_grid_medium.h"

namespace penumbra {

using MediumModel = std::variant<HomogeneousMedium, GridMedium, RgbGridMedium, CloudMedium>;

// A medium's coefficients at a point.
struct MediumProperties {
    Rgb sigmaA, sigmaS;
    Rgb emission;  // Le: the medium emits sigmaA * Le per unit length
    HenyeyGreenstein phase;
};

// exp(-sigma * distance) per channel; an infinite distance through a channel of sigma 0 gives 1.
inline Rgb transmittance(Rgb sigma, float distance) {
    const float d = std::min(distance, std::numeric_limits<float>::max());
    return {std::exp(-sigma.r * d), std::exp(-sigma.g * d), std::exp(-sigma.b * d)};
}

// At most this many tentative collisions along one ray through a medium; beyond them the ray is
// given up, its majorant transmittance 0. A real medium makes a few per optical depth of its
// majorant; a hostile one (a majorant of 1e30 over a long ray) would be tracked without end.
inline constexpr int kMaxCollisionsPerRay = 1 << 22;

namespace detail {

// Delta tracking along one segment of constant majorant sigmaMaj over [tMin, tMax): see
// sampleFreeFlight. Returns false when the tracking stops: the callback stopped it (tMaj then all
// 1) or the ray made kMaxCollisionsPerRay collisions (tMaj then 0).
template <typename Properties, typename NextUniform, typename Callback>
bool trackSegment(float tMin, float tMax, Rgb sigmaMaj, int hero, float& u, Rgb& tMaj, int& collisions,
                  Vec3f origin, Vec3f direction, Properties&& properties, NextUniform&& nextUniform,
                  Callback&& callback) {
    if (sigmaMaj[hero] == 0.0f) {
        tMaj *= transmittance(sigmaMaj, tMax - tMin);
        return true;
    }
    for (float t = tMin;;) {
        const float tNext = t - std::log1p(-u) / sigmaMaj[hero];
        u = nextUniform();
        if (!(tNext < tMax)) {
            tMaj *= transmittance(sigmaMaj, tMax - t);
            return true;
        }
        if (++collisions > kMaxCollisionsPerRay) {
            tMaj = Rgb(0.0f);
            return false;
        }
        tMaj *= transmittance(sigmaMaj, tNext - t);
        if (!callback(tNext, origin + direction * tNext, properties(tNext), sigmaMaj, tMaj)) {
            tMaj = Rgb(1.0f);
            return false;
        }
        tMaj = Rgb(1.0f);
        t = tNext;
    }
}

}  // namespace detail

// Free-flight sampling along origin + t * direction (world; `direction` unit) over [0, tMax):
// tentative collisions at distances drawn from the hero channel's majorant, the first with `u`,
// the rest with nextUniform(). At each, callback(t, p, properties, sigmaMaj, tMaj) with tMaj the
// majorant transmittance since the previous collision; it returns whether to go on. Returns the
// majorant transmittance from the last collision to tMax (all 1 when the callback stopped, all 0
// after kMaxCollisionsPerRay collisions).
template <typename NextUniform, typename Callback>
Rgb sampleFreeFlight(const MediumModel& medium, Vec3f origin, Vec3f direction, float tMax, int hero, float u,
                     NextUniform&& nextUniform, Callback&& callback) {
    Rgb tMaj(1.0f);
    int collisions = 0;
    if (const auto* homogeneous = std::get_if<HomogeneousMedium>(&medium)) {
        const MediumProperties properties{homogeneous->sigmaA, homogeneous->sigmaS, homogeneous->emission,
                                          homogeneous->phase};
        detail::trackSegment(
            0.0f, tMax, homogeneous->sigmaA + homogeneous->sigmaS, hero, u, tMaj, collisions, origin,
            direction, [&](float) { return properties; }, nextUniform, callback);
        return tMaj;
    }
    // A grid medium: its coefficients at a distance along the ray, and its majorants.
    auto track = [&](const MajorantGrid& majorants, const Transform& toWorld, auto&& propertiesAt) {
        const Transform toMedium = toWorld.inverse();
        const Vec3f originInMedium = toMedium.applyPoint(origin),
                    directionInMedium = toMedium.applyVector(direction);
        auto properties = [&](float t) { return propertiesAt(originInMedium + directionInMedium * t); };
        GridMajorantWalk walk(majorants, originInMedium, directionInMedium, 0.0f, tMax);
        // The walk skips the stretches outside the grid, where the majorant is 0.
        for (GridMajorantWalk::Segment s; walk.next(s);) {
            if (!detail::trackSegment(s.tMin, s.tMax, s.sigmaMaj, hero, u, tMaj, collisions, origin,
                                      direction, properties, nextUniform, callback))
                return;
        }
    };
    if (const auto* grid = std::get_if<GridMedium>(&medium)) {
        track(grid->majorants, grid->toWorld, [&](Vec3f p) {
            const float d = grid->densityAt(p);
            return MediumProperties{grid->sigmaA * d, grid->sigmaS * d,
                                    grid->emission.emits() ? grid->emission.at(p) : Rgb(0.0f), grid->phase};
        });
        return tMaj;
    }
    if (const auto* rgbGrid = std::get_if<RgbGridMedium>(&medium)) {
        track(rgbGrid->majorants, rgbGrid->toWorld, [&](Vec3f p) {
            return MediumProperties{rgbGrid->sigmaAAt(p), rgbGrid->sigmaSAt(p), rgbGrid->emissionAt(p),
                                    rgbGrid->phase};
        });
        return tMaj;
    }
    const CloudMedium& cloud = std::get<CloudMedium>(medium);
    track(cloud.majorants, cloud.toWorld, [&](Vec3f p) {
        const float d = cloud.densityAt(p);
        return MediumProperties{cloud.sigmaA * d, cloud.sigmaS * d, Rgb(0.0f), cloud.phase};
    });
    return tMaj;
}

}  // namespace penumbra
