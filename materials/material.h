// The closed set of materials, dispatched with a switch (no virtual call per bounce).
// All directions are in the local shading frame (normal = +z) and point away from the surface.
// Materials are two-sided: a direction pair is evaluated on the side where wo lies.
#pragma once

#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/lambert.h"

namespace penumbra {

struct BsdfSample {
    Vec3f wi;
    Rgb weight;      // f * |cos(theta_i)| / pdf
    float pdf = 0;   // solid-angle density of wi (for a delta lobe: the lobe's choice probability)
    bool isDelta = false;
};

enum class MaterialType : uint8_t { Lambert };

struct Material {
    MaterialType type = MaterialType::Lambert;
    Lambert lambert;

    // BSDF value f(wo, wi), without the cosine.
    Rgb eval(Vec3f wo, Vec3f wi) const {
        switch (type) {
            case MaterialType::Lambert: return lambert.eval(wo, wi);
        }
        return {};
    }
    float pdf(Vec3f wo, Vec3f wi) const {
        switch (type) {
            case MaterialType::Lambert: return lambert.pdf(wo, wi);
        }
        return 0.0f;
    }
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const {
        switch (type) {
            case MaterialType::Lambert: {
                auto s = lambert.sample(wo, u);
                if (!s) return std::nullopt;
                return BsdfSample{s->wi, s->weight, s->pdf, false};
            }
        }
        return std::nullopt;
    }
    // True when every lobe is a delta distribution, so next-event estimation is pointless.
    bool isPurelySpecular() const { return false; }
};

}  // namespace penumbra
