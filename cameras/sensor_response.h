// What the film records of the light that reaches it: pbrt-v4's PixelSensor with its default
// response, the CIE 1931 observer (Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th
// ed., section 5.4.2). The radiance is multiplied by the imaging ratio, exposure time x ISO / 100
// (1 by default: scenes not made for a physical camera render as they are), and, given a white
// balance temperature, adapted (von Kries in Bradford cone space) so that daylight of that
// temperature looks white, as a camera set to that white balance shows it. Both are linear, so
// they are applied to every sample as it reaches the film, and parts of a render still merge
// exactly. pbrt-v4's measured camera responses (its `sensor` curves) are not here.
#pragma once

#include <array>

#include "core/rgb.h"

namespace penumbra {

struct SensorResponse {
    float iso = 100.0f;
    float exposureTime = 1.0f;  // in the shutter's time units (pbrt-v4: shutterclose - shutteropen)
    float whiteBalance = 0.0f;  // kelvin; 0: none
    std::array<Rgb, 3> rows{Rgb(1.0f, 0.0f, 0.0f), Rgb(0.0f, 1.0f, 0.0f), Rgb(0.0f, 0.0f, 1.0f)};

    // The response of these settings: the rows of its matrix on linear sRGB.
    static SensorResponse make(float iso, float exposureTime, float whiteBalance);

    float imagingRatio() const { return exposureTime * iso / 100.0f; }
    Rgb apply(Rgb c) const {
        return {rows[0].r * c.r + rows[0].g * c.g + rows[0].b * c.b,
                rows[1].r * c.r + rows[1].g * c.g + rows[1].b * c.b,
                rows[2].r * c.r + rows[2].g * c.g + rows[2].b * c.b};
    }
};

}  // namespace penumbra
