// The closed set of materials, dispatched with a switch (no virtual call per bounce).
// All directions are in the local shading frame (normal = +z) and point away from the surface.
//
// Sides. Every call takes `front`: whether wo lies on the front side of the GEOMETRIC surface (the
// side its geometric normal points to; the shading normal, hence local +z, is turned to that side
// too). Two-sided reflectors (the default for Lambert, Phong, mirror and conductor) evaluate a
// direction pair on the side where wo lies; a one-sided one is black seen from the back. A
// dielectric's front is its outside: `front` decides whether light enters or leaves it.
//
// Delta lobes (mirror, conductor, both dielectrics) are never evaluated: eval() and pdf() return 0
// and only sample() produces them, with isDelta set and pdf = the probability of the lobe chosen.
#pragma once

#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/conductor.h"
#include "materials/dielectric.h"
#include "materials/lambert.h"
#include "materials/phong.h"

namespace penumbra {

struct BsdfSample {
    Vec3f wi;
    Rgb weight;      // f * |cos(theta_i)| / pdf
    float pdf = 0;   // solid-angle density of wi (for a delta lobe: the lobe's choice probability)
    bool isDelta = false;
    bool isTransmission = false;  // wi lies on the other side of the surface than wo
    // Relative index eta(wi side) / eta(wo side) of a refraction (1 otherwise). The weight of a
    // refraction carries the radiance scale 1 / eta^2; a path's throughput times the product of
    // the eta^2 is free of it (Russian roulette uses that).
    float eta = 1.0f;
};

enum class MaterialType : uint8_t { Lambert, Phong, Dielectric, ThinDielectric, Mirror, Conductor };

struct Material {
    MaterialType type = MaterialType::Lambert;

    // Whether sample() chooses between lobes with its uLobe argument; when not, the integrator
    // need not draw that sample dimension.
    bool usesLobeSample() const {
        return type == MaterialType::Phong || type == MaterialType::Dielectric || type == MaterialType::ThinDielectric;
    }
    bool twoSided = true;  // reflectors only; false: black seen from the back
    Lambert lambert;
    Phong phong;
    Dielectric dielectric;
    ThinDielectric thinDielectric;
    Mirror mirror;
    Conductor conductor;

    // BSDF value f(wo, wi), without the cosine; 0 for delta lobes.
    Rgb eval(Vec3f wo, Vec3f wi, bool front) const {
        if (!twoSided && !front) return Rgb(0.0f);
        switch (type) {
            case MaterialType::Lambert: return lambert.eval(wo, wi);
            case MaterialType::Phong: return phong.eval(wo, wi);
            default: return Rgb(0.0f);
        }
    }
    // Solid-angle density with which sample() produces wi; 0 for delta lobes.
    float pdf(Vec3f wo, Vec3f wi, bool front) const {
        if (!twoSided && !front) return 0.0f;
        switch (type) {
            case MaterialType::Lambert: return lambert.pdf(wo, wi);
            case MaterialType::Phong: return phong.pdf(wo, wi);
            default: return 0.0f;
        }
    }
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool front) const {
        // Lambert, the most common case, is small enough to inline into the integrator.
        if (type == MaterialType::Lambert && (twoSided || front)) return sampleLambert(wo, u);
        return sampleAny(wo, uLobe, u, front);
    }
    std::optional<BsdfSample> sampleLambert(Vec3f wo, Vec2f u) const {
        const auto s = lambert.sample(wo, u);
        if (!s) return std::nullopt;
        return BsdfSample{s->wi, s->weight, s->pdf, false};
    }
    [[gnu::noinline]] std::optional<BsdfSample> sampleAny(Vec3f wo, float uLobe, Vec2f u, bool front) const {
        if (!twoSided && !front) return std::nullopt;
        std::optional<SpecularSample> specular;
        switch (type) {
            case MaterialType::Lambert: return sampleLambert(wo, u);
            case MaterialType::Phong: {
                const auto s = phong.sample(wo, uLobe, u);
                if (!s) return std::nullopt;
                return BsdfSample{s->wi, s->weight, s->pdf, false};
            }
            case MaterialType::Dielectric: specular = dielectric.sample(wo, uLobe, front); break;
            case MaterialType::ThinDielectric: specular = thinDielectric.sample(wo, uLobe); break;
            case MaterialType::Mirror: specular = mirror.sample(wo); break;
            case MaterialType::Conductor: specular = conductor.sample(wo); break;
        }
        if (!specular) return std::nullopt;
        return BsdfSample{specular->wi, specular->weight, specular->pdf, true, specular->isTransmission, specular->eta};
    }
    // True when every lobe is a delta distribution, so next-event estimation is pointless.
    bool isPurelySpecular() const { return type != MaterialType::Lambert && type != MaterialType::Phong; }

    // Absorption coefficient sigma_a (per unit length) of the medium behind the surface, for path
    // segments that reach the surface from its back side; black when there is none.
    Rgb interiorAbsorption() const { return type == MaterialType::Dielectric ? dielectric.absorption : Rgb(0.0f); }

    // Reflectance for the albedo AOV (as denoisers expect it): a diffuse albedo, Phong's kd + ks,
    // a mirror's tint, a conductor's reflectance at normal incidence, white for what transmits.
    Rgb albedo() const {
        switch (type) {
            case MaterialType::Lambert: return lambert.albedo;
            case MaterialType::Phong: return phong.kd + phong.ks;
            case MaterialType::Mirror: return mirror.tint;
            case MaterialType::Conductor: return conductor.reflectance(Vec3f{0.0f, 0.0f, 1.0f});
            default: return Rgb(1.0f);
        }
    }
};

}  // namespace penumbra
