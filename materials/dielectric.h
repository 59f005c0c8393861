// Smooth dielectric interfaces (glass, water): specular reflection and refraction, both delta
// distributions, chosen with probability F and 1 - F so that every sample weighs exactly 1 (times
// the radiance scale 1 / eta^2 on refraction).
//
// Which side is inside is decided by the GEOMETRIC normal, not by the local (shading) frame: the
// caller says whether wo lies on the front (outside) of the surface. The interior has index `eta`
// relative to the exterior. Refraction follows Snell's law about the shading normal; total internal
// reflection happens beyond the critical angle asin(1 / eta) when leaving the interior.
//
// Radiance, not importance, is transported: radiance crossing into a medium of index eta_t from
// eta_i is multiplied by (eta_t / eta_i)^2 (it is L / eta^2 that is invariant along a ray), so a
// camera path sampling the transmitted direction wi gets the weight (1 - F) / (1 - F) / eta^2 with
// eta = eta(wi side) / eta(wo side). The sample reports that relative index so that the integrator
// can keep Russian roulette independent of the scale.
//
// Absorption (Beer-Lambert) inside the medium is not a scattering event: the integrator applies
// exp(-sigma_a * length) to path segments that travel inside (see renderer/path_integrator.h).
//
// ThinDielectric is a window pane: two parallel interfaces so close that the light leaves where it
// entered; reflection and straight-through transmission with all inter-reflections summed
// (pbrt-v4's ThinDielectricBxDF): R' = R + T^2 R / (1 - R^2), T' = 1 - R'. Radiance is not scaled,
// because the light ends up in the medium it came from.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/fresnel.h"

namespace penumbra {

enum class FresnelModel : uint8_t { Exact, Schlick };

constexpr BsdfFlags kSpecularReflection = BsdfFlags::Specular | BsdfFlags::Reflection;
constexpr BsdfFlags kSpecularTransmission = BsdfFlags::Specular | BsdfFlags::Transmission;

struct Dielectric {
    float eta = 1.5f;  // interior index over exterior index, > 0
    FresnelModel fresnel = FresnelModel::Exact;
    Rgb absorption{0.0f, 0.0f, 0.0f};  // sigma_a of the interior, per unit length (0: clear)

    static constexpr BsdfFlags kFlags = kSpecularReflection | kSpecularTransmission;

    // Relative index of the far side seen from wo: eta when wo is outside, 1 / eta inside.
    float relativeEta(bool woOutside) const { return woOutside ? eta : 1.0f / eta; }

    // Reflectance for light leaving along wo (reciprocal: the same for light arriving along wo).
    float reflectance(Vec3f wo, bool woOutside) const {
        const float etaRelative = relativeEta(woOutside);
        const float cosTheta = std::abs(wo.z);
        return fresnel == FresnelModel::Schlick ? fresnelSchlick(cosTheta, etaRelative)
                                                : fresnelDielectric(cosTheta, etaRelative);
    }

    // `woOutside`: whether wo lies on the front (outer) side of the geometric surface.
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f /*u*/, bool woOutside) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float etaRelative = relativeEta(woOutside);
        const float reflect = reflectance(wo, woOutside);
        if (uLobe < reflect) {  // total internal reflection has reflect = 1 > uLobe
            return BsdfSample{reflectAboutZ(wo), Rgb(1.0f), reflect, kSpecularReflection};
        }
        const std::optional<Vec3f> wt = refractAcrossZ(wo, etaRelative);
        if (!wt) {  // cannot happen with reflect < 1 except by rounding at the critical angle
            return BsdfSample{reflectAboutZ(wo), Rgb(1.0f), 1.0f, kSpecularReflection};
        }
        return BsdfSample{*wt, Rgb(1.0f / (etaRelative * etaRelative)), 1.0f - reflect, kSpecularTransmission,
                          etaRelative};
    }
    // One lobe alone, for the walk between a layered material's interfaces (layered_bsdf.h): the
    // reflection or the refraction sampled with probability 1, so pdf 1 and weight F, or (1 - F) /
    // eta^2; none where the lobe carries nothing (no refraction beyond the critical angle).
    std::optional<BsdfSample> sampleLobe(Vec3f wo, bool transmission, bool woOutside) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float reflect = reflectance(wo, woOutside);
        if (!transmission) return BsdfSample{reflectAboutZ(wo), Rgb(reflect), 1.0f, kSpecularReflection};
        const float etaRelative = relativeEta(woOutside);
        const std::optional<Vec3f> wt = refractAcrossZ(wo, etaRelative);
        if (!(reflect < 1.0f) || !wt) return std::nullopt;
        return BsdfSample{*wt, Rgb((1.0f - reflect) / (etaRelative * etaRelative)), 1.0f,
                          kSpecularTransmission, etaRelative};
    }
    Rgb eval(Vec3f, Vec3f, bool) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f, bool) const { return 0.0f; }
    Rgb reflectanceForAov() const { return Rgb(1.0f); }
    // The medium behind the surface (Material::interiorAbsorption).
    Rgb interiorAbsorption() const { return absorption; }
};

struct ThinDielectric {
    float eta = 1.5f;
    FresnelModel fresnel = FresnelModel::Exact;

    static constexpr BsdfFlags kFlags = kSpecularReflection | kSpecularTransmission;

    // Reflectance of the pane, inter-reflections included.
    float reflectance(Vec3f wo) const {
        const float cosTheta = std::abs(wo.z);
        float r = fresnel == FresnelModel::Schlick ? fresnelSchlick(cosTheta, eta)
                                                   : fresnelDielectric(cosTheta, eta);
        if (r < 1.0f) {
            const float t = 1.0f - r;
            r += t * t * r / (1.0f - r * r);
        }
        return r;
    }

    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f /*u*/, bool /*front*/) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float reflect = reflectance(wo);
        if (uLobe < reflect) return BsdfSample{reflectAboutZ(wo), Rgb(1.0f), reflect, kSpecularReflection};
        return BsdfSample{-wo, Rgb(1.0f), 1.0f - reflect, kSpecularTransmission};
    }
    Rgb eval(Vec3f, Vec3f, bool) const { return Rgb(0.0f); }
    float pdf(Vec3f, Vec3f, bool) const { return 0.0f; }
    Rgb reflectanceForAov() const { return Rgb(1.0f); }
};

}  // namespace penumbra
