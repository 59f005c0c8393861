// Emission turns any shape into an area light with constant radiance.
#pragma once

#include "core/rgb.h"

namespace penumbra {

struct Emission {
    Rgb radiance;            // black: the shape does not emit
    bool twoSided = false;   // one-sided lights emit on the front side only
    bool emits() const { return !radiance.isBlack(); }
};

}  // namespace penumbra
