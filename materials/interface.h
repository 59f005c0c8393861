// pbrt-v4's `interface` material: a surface that is only the boundary of a participating medium.
// It neither reflects nor refracts; the volumetric integrator passes rays through it unchanged
// (no path vertex, no bounce counted) and only switches the medium they travel in.
#pragma once

#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/bsdf.h"

namespace penumbra {

struct Interface {
    static constexpr BsdfFlags kFlags = BsdfFlags::None;

    Rgb eval(Vec3f, Vec3f, bool) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f, bool) const { return 0.0f; }
    std::optional<BsdfSample> sample(Vec3f, float, Vec2f, bool) const { return std::nullopt; }
    Rgb reflectanceForAov() const { return Rgb(0.0f); }
};

}  // namespace penumbra
