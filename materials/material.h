// The closed set of materials: a std::variant of the BSDF models, dispatched with std::visit. Every
// model has the same interface, the concept BsdfModel below, so that a model missing a member
// function is a compile error naming it rather than a silent default:
//   static constexpr BsdfFlags kFlags                     the lobes it has
//   Rgb eval(wo, wi, front), float pdf(wo, wi, front)      0 for specular lobes
//   std::optional<BsdfSample> sample(wo, uLobe, u, front)  one lobe, chosen with uLobe when there are several
//   Rgb reflectanceForAov()                                the albedo AOV, as denoisers expect it
// A model with a medium behind its surface (the dielectrics) also has
//   Rgb interiorAbsorption()                               sigma_a of that medium (HasInteriorAbsorption)
// All directions are in the local shading frame (normal = +z) and point away from the surface.
//
// Sides. Every call takes `front`: whether wo lies on the front side of the GEOMETRIC surface (the
// side its geometric normal points to; the shading normal, hence local +z, is turned to that side
// too). Two-sided reflectors (the default for every reflector: Lambert, Phong, mirror, the
// conductors, the coated diffuse) evaluate a direction pair on the side where wo lies; a
// one-sided one is black seen from the back. A dielectric's front is its outside (smooth or rough): `front`
// decides whether light enters or leaves it.
//
// Specular lobes (mirror, conductor, the smooth dielectrics, the smooth coating's reflection) are
// never evaluated: eval() and pdf() leave them out and only sample() produces them, with
// BsdfFlags::Specular and pdf = the lobe's probability.
//
// Textures: any colour or scalar parameter may vary over the surface (textures/texture.h). The
// models themselves hold plain values; a textured Material also holds, per textured parameter, the
// texture and the function that writes its value into the model. At a shading point the integrator
// asks at(query) for a copy with those values written in; untextured materials (isTextured() false)
// are used as they are, so they cost nothing more. A bump or normal map (perturbation()) is held
// with the textures, and turns the shading normal before the material is evaluated.
//
// Adding a material: its header here, one alternative in MaterialModel, one row in the scene
// loader's material table (scenes/material_reader.cpp), and its tests.
#pragma once

#include <concepts>
#include <cstddef>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "core/check.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/coated_diffuse.h"
#include "materials/conductor.h"
#include "materials/dielectric.h"
#include "materials/diffuse_transmission.h"
#include "materials/hair_bsdf.h"
#include "materials/interface.h"
#include "materials/lambert.h"
#include "materials/layered_bsdf.h"
#include "materials/material_mix.h"
#include "materials/measured_bsdf.h"
#include "materials/normal_perturbation.h"
#include "materials/phong.h"
#include "materials/rough_conductor.h"
#include "materials/rough_dielectric.h"
#include "materials/subsurface_boundary.h"
#include "textures/texture.h"

namespace penumbra {

// What Material's dispatch calls on every model.
template <typename M>
concept BsdfModel = std::copyable<M> && requires(const M& m, Vec3f w, float uLobe, Vec2f u, bool front) {
    { M::kFlags } -> std::convertible_to<BsdfFlags>;
    { m.eval(w, w, front) } -> std::same_as<Rgb>;
    { m.pdf(w, w, front) } -> std::same_as<float>;
    { m.sample(w, uLobe, u, front) } -> std::same_as<std::optional<BsdfSample>>;
    { m.reflectanceForAov() } -> std::same_as<Rgb>;
};

// A model with an absorbing medium behind its surface: what Material::interiorAbsorption asks.
template <typename M>
concept HasInteriorAbsorption = requires(const M& m) {
    { m.interiorAbsorption() } -> std::same_as<Rgb>;
};

using MaterialModel = std::variant<Lambert, Phong, Dielectric, ThinDielectric, Mirror, Conductor,
                                   RoughConductor, RoughDielectric, CoatedDiffuse, RoughCoatedDiffuse,
                                   DiffuseTransmission, HairBsdf, SubsurfaceBoundary<Dielectric>,
                                   SubsurfaceBoundary<RoughDielectric>, MeasuredBsdf, LayeredBsdf, Interface>;

namespace detail {
// Viable only for a BsdfModel: otherwise the compiler names the model and what it misses.
template <BsdfModel M>
constexpr bool isABsdfModel() {
    return true;
}
template <typename... Models>
constexpr bool everyAlternativeIsABsdfModel(const std::variant<Models...>*) {
    return (isABsdfModel<Models>() && ...);
}
}  // namespace detail
static_assert(detail::everyAlternativeIsABsdfModel(static_cast<const MaterialModel*>(nullptr)),
              "every alternative of MaterialModel is a BsdfModel");

// One textured parameter: its texture, and how a value of it is written into the model (the scene
// loader's material table knows which member of which model a key names).
struct TexturedParameter {
    Texture texture;
    void (*apply)(MaterialModel& model, Rgb value);
};

class Material {
public:
    Material() : Material(Lambert{}) {}
    // `twoSided` applies to reflectors; false makes them black seen from the back.
    Material(MaterialModel model, bool twoSided = true)
        : model_(std::move(model)),
          twoSided_(twoSided),
          flags_(std::visit([](const auto& m) { return m.kFlags; }, model_)),
          usesLobeSample_(hasSeveralLobes(flags_)),
          purelySpecular_(penumbra::isPurelySpecular(flags_)) {
        variesOverSurface_ = isFiber();
        PENUMBRA_CHECK(std::visit(
                           [](const auto& m) {
                               if constexpr (requires { requires std::same_as<decltype(m.eta), float>; })
                                   return m.eta > 0.0f;
                               else
                                   return true;
                           },
                           model_),
                       "a model's relative index of refraction is positive (the scene loader checks it)");
    }
    // `model` holds the untextured parameters' values; each of `textures` overrides one parameter;
    // `perturbation` turns the shading normal (a bump or normal map: materials/normal_perturbation.h).
    Material(MaterialModel model, bool twoSided, std::vector<TexturedParameter> textures,
             std::optional<NormalPerturbation> perturbation = std::nullopt)
        : Material(std::move(model), twoSided) {
        if (textures.empty() && !perturbation) return;
        for (const TexturedParameter& p : textures) needsFootprint_ |= p.texture.needsFootprint();
        if (perturbation) needsFootprint_ |= perturbation->texture.needsFootprint();
        textures_ =
            std::make_shared<const SurfaceTextures>(SurfaceTextures{std::move(textures), perturbation});
        variesOverSurface_ = true;
    }

    // A mix of two of the scene's materials (materials/material_mix.h): it has no BSDF of its own,
    // and the integrator shades the one mix() chooses instead (resolveMix below).
    static Material mixOf(MaterialMix mix) {
        Material m;
        m.mix_ = std::make_shared<const MaterialMix>(std::move(mix));
        m.variesOverSurface_ = true;
        return m;
    }
    const MaterialMix* mix() const { return mix_.get(); }

    // Whether this is a fiber's BSDF (hair), which depends on where across the fiber a ray arrived
    // (a curve's v, geometry/curves.h): withFiberOffset gives it that offset at a shading point.
    bool isFiber() const { return std::holds_alternative<HairBsdf>(model_); }
    Material withFiberOffset(float h) const {
        Material m = *this;
        std::get<HairBsdf>(m.model_).h = h;
        return m;
    }

    // Whether anything varies over the surface (textured parameters or a perturbed normal).
    bool isTextured() const { return textures_ != nullptr; }
    // Whether the material shaded at a point may differ from this one (a mix's choice, textures,
    // a fiber's offset): one flag, so the integrators' bounce loop tests both at the cost of one.
    bool variesOverSurface() const { return variesOverSurface_; }
    // Whether a texture lookup needs the pixel's footprint (textures/texture_footprint.h).
    bool needsFootprint() const { return needsFootprint_; }
    const std::vector<TexturedParameter>* texturedParameters() const {
        return textures_ ? &textures_->parameters : nullptr;
    }
    const NormalPerturbation* perturbation() const {
        return textures_ && textures_->perturbation ? &*textures_->perturbation : nullptr;
    }
    // This material at a shading point: its textured parameters evaluated there, untextured.
    [[gnu::noinline]] Material at(const TextureQuery& query) const {
        MaterialModel model = model_;
        for (const TexturedParameter& p : textures_->parameters) p.apply(model, p.texture.evaluate(query));
        return Material(std::move(model), twoSided_);
    }

    const MaterialModel& model() const { return model_; }
    bool twoSided() const { return twoSided_; }
    BsdfFlags flags() const { return flags_; }
    // Whether sample() chooses between lobes with its uLobe argument; when not, the integrator
    // need not draw that sample dimension.
    bool usesLobeSample() const { return usesLobeSample_; }
    // Whether the surface is only a medium boundary (materials/interface.h): no path vertex.
    bool isInterface() const { return std::holds_alternative<Interface>(model_); }
    // True when every lobe is a delta distribution, so next-event estimation is pointless.
    bool isPurelySpecular() const { return purelySpecular_; }

    // Lambert, the most common case, is small enough to inline into the integrator; the other
    // models are visited out of line (bench/README.md, "Speed tricks").

    // BSDF value f(wo, wi), without the cosine; 0 for specular lobes.
    Rgb eval(Vec3f wo, Vec3f wi, bool front) const {
        if (!twoSided_ && !front) return Rgb(0.0f);
        if (const Lambert* lambert = std::get_if<Lambert>(&model_)) return lambert->eval(wo, wi, front);
        return evalOutOfLine(wo, wi, front);
    }
    // Solid-angle density with which sample() produces wi; 0 for specular lobes.
    float pdf(Vec3f wo, Vec3f wi, bool front) const {
        if (!twoSided_ && !front) return 0.0f;
        if (const Lambert* lambert = std::get_if<Lambert>(&model_)) return lambert->pdf(wo, wi, front);
        return pdfOutOfLine(wo, wi, front);
    }
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool front) const {
        if (const Lambert* lambert = std::get_if<Lambert>(&model_); lambert && (twoSided_ || front))
            return lambert->sample(wo, u);
        return sampleOutOfLine(wo, uLobe, u, front);
    }

    // Absorption coefficient sigma_a (per unit length) of the medium behind the surface, for path
    // segments that reach the surface from its back side; black when there is none.
    // Only the models that declare one (HasInteriorAbsorption) are tested, in the variant's order.
    Rgb interiorAbsorption() const { return interiorAbsorptionFrom(); }

    // A subsurface material's interior coefficients (sigma_a, sigma_s) at this shading point,
    // where textures give them (materials/subsurface_boundary.h); none otherwise.
    std::optional<std::pair<Rgb, Rgb>> texturedInterior() const {
        if (const auto* b = std::get_if<SubsurfaceBoundary<Dielectric>>(&model_))
            return b->interior.coefficients();
        if (const auto* b = std::get_if<SubsurfaceBoundary<RoughDielectric>>(&model_))
            return b->interior.coefficients();
        return std::nullopt;
    }

    // Reflectance for the albedo AOV (as denoisers expect it): a diffuse albedo (a coated base's
    // too), Phong's kd + ks, a mirror's tint, a conductor's reflectance at normal incidence, white
    // for what transmits. Out of line: asked once per camera ray, its visit of every model (complex
    // Fresnel for conductors) inlined into the integrator's loop made that loop slower
    // (bench/README.md, "Speed tricks").
    [[gnu::noinline]] Rgb albedo() const {
        return std::visit([](const auto& m) { return m.reflectanceForAov(); }, model_);
    }

private:
    // The first alternative from I on that declares an interior absorption, when model_ holds it.
    template <size_t I = 0>
    Rgb interiorAbsorptionFrom() const {
        if constexpr (I == std::variant_size_v<MaterialModel>) {
            return Rgb(0.0f);
        } else {
            using M = std::variant_alternative_t<I, MaterialModel>;
            if constexpr (HasInteriorAbsorption<M>)
                if (const M* m = std::get_if<I>(&model_)) return m->interiorAbsorption();
            return interiorAbsorptionFrom<I + 1>();
        }
    }

    [[gnu::noinline]] Rgb evalOutOfLine(Vec3f wo, Vec3f wi, bool front) const {
        const Rgb f = std::visit([&](const auto& m) { return m.eval(wo, wi, front); }, model_);
        PENUMBRA_CHECK(!(f.minComponent() < 0.0f), "a BSDF value is never negative");
        return f;
    }
    [[gnu::noinline]] float pdfOutOfLine(Vec3f wo, Vec3f wi, bool front) const {
        const float p = std::visit([&](const auto& m) { return m.pdf(wo, wi, front); }, model_);
        PENUMBRA_CHECK(!(p < 0.0f), "a density is never negative");
        return p;
    }
    [[gnu::noinline]] std::optional<BsdfSample> sampleOutOfLine(Vec3f wo, float uLobe, Vec2f u,
                                                                bool front) const {
        if (!twoSided_ && !front) return std::nullopt;
        const std::optional<BsdfSample> s =
            std::visit([&](const auto& m) { return m.sample(wo, uLobe, u, front); }, model_);
        PENUMBRA_CHECK(!s || (s->pdf > 0.0f && s->weight.isFinite() && s->weight.minComponent() >= 0.0f),
                       "a BSDF sample has a positive density and a finite, non-negative weight");
        return s;
    }

    MaterialModel model_;
    struct SurfaceTextures {
        std::vector<TexturedParameter> parameters;
        std::optional<NormalPerturbation> perturbation;
    };
    std::shared_ptr<const SurfaceTextures> textures_;  // null: untextured
    std::shared_ptr<const MaterialMix> mix_;           // null: not a mix
    bool twoSided_ = true;
    bool needsFootprint_ = false;
    bool variesOverSurface_ = false;  // textures_, mix_ or a fiber
    BsdfFlags flags_;
    // Derived from flags_ once: the integrator asks at every vertex.
    bool usesLobeSample_;
    bool purelySpecular_;
};

// The material shaded at a point: `index`'s, or for a mix the one it chooses there (following
// mixes of mixes; the scene loader refuses cycles).
inline uint32_t resolveMix(const std::vector<Material>& materials, uint32_t index, Vec3f p, Vec3f wo,
                           Vec2f uv, Vec3f n = {0.0f, 0.0f, 0.0f}) {
    while (const MaterialMix* mix = materials[index].mix()) index = mix->choose(p, n, wo, uv, index);
    return index;
}

}  // namespace penumbra
