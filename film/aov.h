// What a camera ray's first hit tells besides radiance: the arbitrary output variables (AOVs)
// the film sums next to the beauty (albedo, normal and depth, e.g. for denoisers and compositing).
#pragma once

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

struct FirstHitAovs {
    bool hit = false;                // false: the camera ray left the scene (the other fields are unused)
    float distance = 0.0f;           // from the ray origin to the first hit, in scene units
    Vec3f normal{0.0f, 0.0f, 0.0f};  // unit shading normal at the first hit (on the shape's front side)
    Rgb albedo{0.0f};                // reflectance of the first hit's material (Material::albedo)
};

}  // namespace penumbra
