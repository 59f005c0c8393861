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

// A textured emitter's radiance at `uv`, looked up without a footprint (the finest level): the
// same for a hit and for next-event estimation's sample of the same point.
inline Rgb emittedRadiance(const Texture& texture, Vec2f uv) {
    TextureQuery query;
    query.uv = uv;
    return texture.evaluate(query);
}

}  // namespace penumbra
