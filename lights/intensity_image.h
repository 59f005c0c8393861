// A goniometric light's profile given as an image (pbrt-v4's GoniometricLight "filename"): a
// square image over the sphere of directions in Clarberg's equal-area map (core/equal_area.h), one
// value per texel (the mean of its channels, as pbrt-v4 takes it), looked up at the nearest texel.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "core/equal_area.h"
#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

class IntensityImage {
public:
    // `texels` rows top to bottom, resolution x resolution of them, each finite and >= 0.
    IntensityImage(int resolution, const std::vector<Rgb>& texels) : resolution_(resolution) {
        values_.reserve(texels.size());
        double sum = 0.0;
        for (const Rgb& t : texels) {
            values_.push_back((t.r + t.g + t.b) / 3.0f);
            sum += values_.back();
        }
        // Every texel covers the same solid angle, 4 pi / resolution^2: the nearest-texel profile's
        // integral over the sphere is exactly 4 pi times the mean (pbrt-v4's GoniometricLight::Phi).
        totalFlux_ = values_.empty() ? 0.0 : 4.0 * std::numbers::pi * sum / double(values_.size());
    }

    // The intensity towards `localDirection` (any length): +z the map's pole, as pbrt-v4's
    // light space after its y-z swap.
    float intensity(Vec3f localDirection) const {
        const float lengthSq = lengthSquared(localDirection);
        if (!(lengthSq > 0.0f) || values_.empty()) return 0.0f;
        const Vec2f st = equalAreaSphereToSquare(localDirection / std::sqrt(lengthSq));
        const int x = std::clamp(int(st.x * float(resolution_)), 0, resolution_ - 1);
        const int y = std::clamp(int(st.y * float(resolution_)), 0, resolution_ - 1);
        return values_[size_t(y) * size_t(resolution_) + size_t(x)];
    }
    double totalFlux() const { return totalFlux_; }
    int resolution() const { return resolution_; }

private:
    int resolution_ = 0;
    std::vector<float> values_;
    double totalFlux_ = 0.0;
};

}  // namespace penumbra
