// Emission turns any shape into an area light: a constant radiance, or a texture over the shape's
// (u, v) (textures/texture.h).
#pragma once

#include <memory>

#include "core/rgb.h"
#include "textures/texture.h"

namespace penumbra {

struct Emission {
    // Without a texture, the radiance (black: the shape does not emit); with one, the radiance
    // averaged over the texture, which sets the light's power for next-event estimation.
    Rgb radiance;
    bool twoSided = false;                   // one-sided lights emit on the front side only
    std::shared_ptr<const Texture> texture;  // null: constant radiance
    bool emits() const { return !radiance.isBlack(); }
};

}  // namespace penumbra
