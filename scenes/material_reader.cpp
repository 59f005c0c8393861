#include "scenes/material_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "materials/layered_bsdf.h"
#include "materials/measured_bsdf_reader.h"
#include "materials/subsurface_albedo.h"
#include "scenes/medium_reader.h"
#include "scenes/name_reference.h"
#include "scenes/texture_reader.h"
#include "scenes/type_table.h"

namespace penumbra {

namespace {

// What a material's reader needs besides its JSON: the scene file's folder (for image files) and
// the textured parameters it collects.
struct MaterialContext {
    const std::filesystem::path& folder;
    std::vector<TexturedParameter> textures;
    std::optional<HomogeneousMedium> interior;  // a subsurface material's medium
    // The measured BRDFs read so far for this scene, by canonical path: each file is read once.
    std::map<std::filesystem::path, std::shared_ptr<const MeasuredBrdfTables>>& measuredFiles;
};

using ApplyColor = void (*)(MaterialModel&, Rgb);

// A colour parameter within [min, max]: its constant value, or (a texture object) the default
// value, with the texture recorded to override it at each shading point through `apply`.
Rgb readColorParameter(const JsonValue& value, float min, float max, Rgb defaultValue,
                       MaterialContext& context, ApplyColor apply) {
    if (!isTextureValue(value)) return value.rgb(min, max);
    context.textures.push_back({readTexture(value, context.folder, min, max), apply});
    return defaultValue;
}

// Texture values clamped to what the parameter allows (images may hold anything).
Rgb clampedColor(Rgb c, float max = 1.0f) {
    return {std::clamp(c.r, 0.0f, max), std::clamp(c.g, 0.0f, max), std::clamp(c.b, 0.0f, max)};
}

// How "roughness" r gives the slopes alpha ("roughness_mapping"): r^2 (the default: Disney's,
// Cycles' and Blender's), sqrt(r) (pbrt-v4's `remaproughness true`) or r itself (its
// `remaproughness false`).
enum class RoughnessMapping : uint8_t { Squared, SquareRoot, Identity };

RoughnessMapping readRoughnessMapping(const JsonValue& material) {
    if (auto v = material.member("roughness_mapping")) {
        if (!material.member("roughness")) v->fail("\"roughness_mapping\" maps a \"roughness\": give one");
        return RoughnessMapping(v->choice({"squared", "sqrt", "identity"}));
    }
    return RoughnessMapping::Squared;
}

float mappedRoughness(float r, RoughnessMapping mapping) {
    switch (mapping) {
        case RoughnessMapping::Squared:
            return roughnessToAlpha(r);
        case RoughnessMapping::SquareRoot:
            return std::sqrt(r);
        case RoughnessMapping::Identity:
            break;
    }
    return r;
}

// Where a textured roughness writes its slopes: a model's microfacet distribution (of its
// interface, for a subsurface boundary; of its coat or of its base, for a layered material).
using DistributionAccess = MicrofacetDistribution& (*)(MaterialModel&);

template <class Model>
MicrofacetDistribution& distributionOf(Model& model) {
    return model.distribution;
}
template <class Surface>
MicrofacetDistribution& distributionOf(SubsurfaceBoundary<Surface>& model) {
    return model.surface.distribution;
}
template <class Model>
MicrofacetDistribution& distributionIn(MaterialModel& m) {
    return distributionOf(std::get<Model>(m));
}
MicrofacetDistribution& layeredCoatDistribution(MaterialModel& m) {
    return std::get<LayeredBsdf>(m).coatDistribution;
}
MicrofacetDistribution& layeredConductorDistribution(MaterialModel& m) {
    return std::get<LayeredBsdf>(m).conductorDistribution;
}

// Which slopes a textured roughness sets: both, or (one texture per axis) those along u or along v.
enum class RoughnessAxis : uint8_t { Both, U, V };

// A textured roughness (its first channel, clamped to [0, 1]) as slopes, mapped by `kMapping`.
template <DistributionAccess kAccess, RoughnessMapping kMapping, RoughnessAxis kAxis>
void setRoughness(MaterialModel& m, Rgb value) {
    MicrofacetDistribution& d = kAccess(m);
    const float alpha = std::max(mappedRoughness(std::clamp(value.r, 0.0f, 1.0f), kMapping), 1e-4f);
    if (kAxis != RoughnessAxis::V) d.alphaX = alpha;
    if (kAxis != RoughnessAxis::U) d.alphaY = alpha;
}

template <DistributionAccess kAccess, RoughnessAxis kAxis>
ApplyColor roughnessSetter(RoughnessMapping mapping) {
    switch (mapping) {
        case RoughnessMapping::Squared:
            return setRoughness<kAccess, RoughnessMapping::Squared, kAxis>;
        case RoughnessMapping::SquareRoot:
            return setRoughness<kAccess, RoughnessMapping::SquareRoot, kAxis>;
        case RoughnessMapping::Identity:
            break;
    }
    return setRoughness<kAccess, RoughnessMapping::Identity, kAxis>;
}

// The textured-roughness setter of the distribution `kAccess` names, for `mapping` and `axis`.
template <DistributionAccess kAccess>
ApplyColor roughnessSetter(RoughnessMapping mapping, RoughnessAxis axis) {
    switch (axis) {
        case RoughnessAxis::Both:
            return roughnessSetter<kAccess, RoughnessAxis::Both>(mapping);
        case RoughnessAxis::U:
            return roughnessSetter<kAccess, RoughnessAxis::U>(mapping);
        case RoughnessAxis::V:
            break;
    }
    return roughnessSetter<kAccess, RoughnessAxis::V>(mapping);
}

// A "roughness" that is a texture, or an array (along u, along v) of which one or both are.
bool isTexturedRoughness(const JsonValue& roughness) {
    if (isTextureValue(roughness)) return true;
    return roughness.json().is_array() && roughness.arraySize() == 2 &&
           (isTextureValue(roughness.element(0)) || isTextureValue(roughness.element(1)));
}

// A textured "roughness", recorded to set the slopes `kAccess` names at each shading point: one
// texture for both axes, or one per axis (a number for the other is already in the model).
template <DistributionAccess kAccess>
void addTexturedRoughness(const JsonValue& material, MaterialContext& context) {
    const JsonValue roughness = *material.member("roughness");
    const RoughnessMapping mapping = readRoughnessMapping(material);
    if (isTextureValue(roughness)) {
        context.textures.push_back({readTexture(roughness, context.folder, 0.0f, 1.0f),
                                    roughnessSetter<kAccess>(mapping, RoughnessAxis::Both)});
        return;
    }
    for (size_t k = 0; k < 2; ++k)
        if (const JsonValue axis = roughness.element(k); isTextureValue(axis))
            context.textures.push_back(
                {readTexture(axis, context.folder, 0.0f, 1.0f),
                 roughnessSetter<kAccess>(mapping, k == 0 ? RoughnessAxis::U : RoughnessAxis::V)});
}

FresnelModel readFresnel(const JsonValue& value) {
    return value.choice({"exact", "schlick"}) == 0 ? FresnelModel::Exact : FresnelModel::Schlick;
}

// "absorption": {"color": c, "distance": d}: light keeps the fraction c (per channel, in (0, 1])
// after travelling d inside, so sigma_a = -ln(c) / d.
Rgb readAbsorption(const JsonValue& value) {
    const JsonObject object(value, {"color", "distance"});
    const JsonValue colorValue = object.require("color");
    const Rgb color = colorValue.rgb(0.0f, 1.0f);
    for (int c = 0; c < 3; ++c)
        if (!(color[c] > 0.0f))
            colorValue.failExpected(
                "a transmittance in (0, 1] per channel (0 would absorb everything at any distance)");
    const float distance = object.require("distance").numberAbove(0.0f);
    return {-std::log(color.r) / distance, -std::log(color.g) / distance, -std::log(color.b) / distance};
}

bool readTwoSided(const JsonValue& material) {
    const auto v = material.member("two_sided");
    return v ? v->boolean() : true;
}

Material readLambert(const JsonValue& material, MaterialContext& context) {
    Lambert lambert;
    if (auto v = material.member("albedo"))
        lambert.albedo = readColorParameter(
            *v, 0.0f, 1.0f, lambert.albedo, context,
            [](MaterialModel& m, Rgb c) { std::get<Lambert>(m).albedo = clampedColor(c); });
    return Material(lambert, readTwoSided(material), std::move(context.textures));
}

// Textured diffuse and specular colours are each clamped to [0, 1]; their sum is not checked.
Material readPhong(const JsonValue& material, MaterialContext& context) {
    Phong phong;
    if (auto v = material.member("diffuse"))
        phong.kd = readColorParameter(*v, 0.0f, 1.0f, phong.kd, context, [](MaterialModel& m, Rgb c) {
            std::get<Phong>(m).kd = clampedColor(c);
        });
    if (auto v = material.member("exponent")) phong.exponent = v->numberAtLeast(0.0f);
    const bool twoSided = readTwoSided(material);
    if (auto v = material.member("specular")) {
        phong.ks = readColorParameter(*v, 0.0f, 1.0f, phong.ks, context, [](MaterialModel& m, Rgb c) {
            std::get<Phong>(m).ks = clampedColor(c);
        });
        // diffuse alone is at most 1, so a sum above 1 always involves a given specular.
        static constexpr const char* kChannels[] = {"red", "green", "blue"};
        for (int c = 0; c < 3; ++c)
            if (phong.kd[c] + phong.ks[c] > 1.0f)
                v->fail(fmt::format(
                    "diffuse + specular must not exceed 1 in any channel (energy conservation), but "
                    "the {} channel has {} + {} = {}",
                    kChannels[c], phong.kd[c], phong.ks[c], phong.kd[c] + phong.ks[c]));
    }
    return Material(phong, twoSided, std::move(context.textures));
}

Material readThinDielectric(const JsonValue& material, MaterialContext&) {
    ThinDielectric thin;
    if (auto v = material.member("eta")) thin.eta = v->numberAbove(0.0f);
    if (auto v = material.member("fresnel")) thin.fresnel = readFresnel(*v);
    return Material(thin);
}

Material readMirror(const JsonValue& material, MaterialContext& context) {
    Mirror mirror;
    if (auto v = material.member("tint"))
        mirror.tint = readColorParameter(*v, 0.0f, 1.0f, mirror.tint, context, [](MaterialModel& m, Rgb c) {
            std::get<Mirror>(m).tint = clampedColor(c);
        });
    return Material(mirror, readTwoSided(material), std::move(context.textures));
}

// A rough surface's microfacet distribution: "distribution" ("ggx" or "beckmann") and the slopes
// from "roughness" r in [0, 1] (alpha = r^2, or as "roughness_mapping" says) or "alpha" > 0, each a
// number or [along u, along v]
// for an anisotropic surface; none when no roughness is given.
// A textured "roughness" (an object, or an array along u and v of which one or both are objects)
// gives a rough surface whose slopes come from the textures' first channel at each point (`textured`
// is set; the slopes returned are placeholders where a texture will write them).
std::optional<MicrofacetDistribution> readDistribution(const JsonValue& material, bool* textured = nullptr) {
    const auto roughness = material.member("roughness");
    const auto alpha = material.member("alpha");
    const auto kind = material.member("distribution");
    if (roughness && alpha) alpha->fail("give either \"roughness\" or \"alpha\", not both");
    if (!roughness && !alpha) {
        if (kind) kind->fail("a distribution needs a \"roughness\" or an \"alpha\"");
        return std::nullopt;
    }
    const JsonValue& value = roughness ? *roughness : *alpha;
    const RoughnessMapping mapping = readRoughnessMapping(material);
    auto read = [&](const JsonValue& v) {
        if (roughness) {
            const float r = v.number();
            if (!(r >= 0.0f && r <= 1.0f))
                v.failExpected(mapping == RoughnessMapping::Squared
                                   ? "a roughness in [0, 1] (alpha = roughness^2)"
                               : mapping == RoughnessMapping::SquareRoot
                                   ? "a roughness in [0, 1] (alpha = sqrt(roughness))"
                                   : "a roughness in [0, 1] (alpha = roughness)");
            return mappedRoughness(r, mapping);
        }
        const float a = v.number();
        if (!(a > 0.0f && a <= 4.0f))
            v.failExpected("an alpha in (0, 4] (0 is a smooth surface: use the smooth material)");
        return a;
    };
    if (roughness && isTexturedRoughness(*roughness)) {
        if (!textured) roughness->fail("this material's roughness cannot be a texture");
        *textured = true;
        MicrofacetDistribution d;
        if (kind)
            d.kind = kind->choice({"ggx", "beckmann"}) == 0 ? MicrofacetKind::Ggx : MicrofacetKind::Beckmann;
        d.alphaX = d.alphaY = 0.25f;        // until a texture's value is written in
        if (!isTextureValue(*roughness)) {  // one texture per axis, or a number for one of them
            if (!isTextureValue(roughness->element(0))) d.alphaX = read(roughness->element(0));
            if (!isTextureValue(roughness->element(1))) d.alphaY = read(roughness->element(1));
        }
        return d;
    }
    MicrofacetDistribution d;
    if (kind)
        d.kind = kind->choice({"ggx", "beckmann"}) == 0 ? MicrofacetKind::Ggx : MicrofacetKind::Beckmann;
    if (!value.json().is_array()) {
        d.alphaX = d.alphaY = read(value);
        return d;
    }
    if (value.arraySize() != 2) value.failExpected("a number or an array of 2 numbers (along u, along v)");
    d.alphaX = read(value.element(0));
    d.alphaY = read(value.element(1));
    return d;
}

// Narrower than kSmoothAlpha in both directions (or no roughness given): the smooth model.
bool isSmooth(const std::optional<MicrofacetDistribution>& d) {
    return !d || std::max(d->alphaX, d->alphaY) < kSmoothAlpha;
}

// Keeps a rough lobe's slopes where float arithmetic holds (pbrt-v4 clamps the same way).
MicrofacetDistribution clampedForRendering(MicrofacetDistribution d) {
    d.alphaX = std::max(d.alphaX, 1e-4f);
    d.alphaY = std::max(d.alphaY, 1e-4f);
    return d;
}

Rgb readConductorEta(const JsonValue& material) {
    const JsonValue etaValue = material.requiredMember("eta");
    const Rgb eta = etaValue.rgb(0.0f);
    for (int c = 0; c < 3; ++c)
        if (!(eta[c] > 0.0f)) etaValue.failExpected("a number or an array of 3 numbers (r, g, b), each > 0");
    return eta;
}

// A conductor `Model`'s eta and k from a reflectance at normal incidence (a texture's value).
template <class Model>
void setConductorReflectance(MaterialModel& m, Rgb r) {
    Model& model = std::get<Model>(m);
    model.eta = Rgb(1.0f);
    model.k = conductorKForReflectance(r);
}

// A conductor `Model`'s eta or k from a texture's value.
template <class Model>
void setConductorEta(MaterialModel& m, Rgb eta) {
    std::get<Model>(m).eta = {std::max(eta.r, 1e-4f), std::max(eta.g, 1e-4f), std::max(eta.b, 1e-4f)};
}
template <class Model>
void setConductorK(MaterialModel& m, Rgb k) {
    std::get<Model>(m).k = {std::max(k.r, 0.0f), std::max(k.g, 0.0f), std::max(k.b, 0.0f)};
}

// How textures of a conductor's index reach its model.
struct ConductorSetters {
    ApplyColor reflectance, eta, k;
};
template <class Model>
constexpr ConductorSetters kConductorSetters{setConductorReflectance<Model>, setConductorEta<Model>,
                                             setConductorK<Model>};

// A conductor's complex index (eta, k): "eta" and "k" (colours or textures), or "reflectance" (a
// colour or a texture: pbrt-v4's artist-friendly conductor, eta 1).
std::pair<Rgb, Rgb> readConductorIndex(const JsonValue& material, MaterialContext& context,
                                       const ConductorSetters& setters) {
    Rgb eta(1.0f), k;
    if (auto v = material.member("reflectance")) {
        if (material.member("eta") || material.member("k"))
            v->fail("a conductor takes \"eta\" and \"k\", or \"reflectance\", not both");
        const Rgb r = readColorParameter(*v, 0.0f, 1.0f, Rgb(0.5f), context, setters.reflectance);
        return {eta, conductorKForReflectance(r)};
    }
    // Textured eta and k (pbrt-v4's conductor takes spectrum textures of both), kept where the
    // complex Fresnel term holds: eta > 0, k >= 0.
    const JsonValue etaValue = material.requiredMember("eta"), kValue = material.requiredMember("k");
    if (isTextureValue(etaValue))
        eta = readColorParameter(etaValue, 0.0f, std::numeric_limits<float>::max(), Rgb(1.0f), context,
                                 setters.eta);
    else
        eta = readConductorEta(material);
    k = isTextureValue(kValue) ? readColorParameter(kValue, 0.0f, std::numeric_limits<float>::max(),
                                                    Rgb(1.0f), context, setters.k)
                               : kValue.rgb(0.0f);
    return {eta, k};
}

// "conductor" and "rough_conductor" (whose table row also accepts the roughness keys): its index
// (readConductorIndex) and a "tint".
Material readConductor(const JsonValue& material, MaterialContext& context) {
    bool texturedRoughness = false;
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material, &texturedRoughness);
    const bool smooth = isSmooth(distribution) && !texturedRoughness;
    const auto [eta, k] = readConductorIndex(
        material, context, smooth ? kConductorSetters<Conductor> : kConductorSetters<RoughConductor>);
    Rgb tint(1.0f);
    if (auto v = material.member("tint")) {
        tint = smooth ? readColorParameter(
                            *v, 0.0f, 1.0f, tint, context,
                            [](MaterialModel& m, Rgb c) { std::get<Conductor>(m).tint = clampedColor(c); })
                      : readColorParameter(*v, 0.0f, 1.0f, tint, context, [](MaterialModel& m, Rgb c) {
                            std::get<RoughConductor>(m).tint = clampedColor(c);
                        });
    }
    if (smooth) return Material(Conductor{eta, k, tint}, readTwoSided(material), std::move(context.textures));
    if (texturedRoughness) addTexturedRoughness<distributionIn<RoughConductor>>(material, context);
    return Material(RoughConductor{eta, k, clampedForRendering(*distribution), tint}, readTwoSided(material),
                    std::move(context.textures));
}

// "dielectric" and "rough_dielectric", likewise.
Material readDielectric(const JsonValue& material, MaterialContext& context) {
    Dielectric smooth;
    if (auto v = material.member("eta")) smooth.eta = v->numberAbove(0.0f);
    if (auto v = material.member("fresnel")) smooth.fresnel = readFresnel(*v);
    if (auto v = material.member("absorption")) smooth.absorption = readAbsorption(*v);
    bool texturedRoughness = false;
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material, &texturedRoughness);
    if (isSmooth(distribution) && !texturedRoughness) return Material(smooth);
    if (texturedRoughness) addTexturedRoughness<distributionIn<RoughDielectric>>(material, context);
    return Material(
        RoughDielectric{smooth.eta, smooth.fresnel, smooth.absorption, clampedForRendering(*distribution)},
        true, std::move(context.textures));
}

// The keys of the layered model (materials/layered_bsdf.h) besides its coat and its base.
constexpr std::array<std::string_view, 5> kLayeredSlabKeys{"thickness", "medium_albedo", "g", "max_depth",
                                                           "samples"};

// The slab between a layered material's interfaces and its walk: "thickness" (a number >= 0 or a
// texture; pbrt-v4's 0.01), "medium_albedo" (a colour or a texture; black: the slab only absorbs),
// "g" (its Henyey-Greenstein asymmetry), "max_depth" (10) and "samples" (1) of the walk.
void readLayeredSlab(const JsonValue& material, MaterialContext& context, LayeredBsdf& layered) {
    static constexpr float kThinnest = std::numeric_limits<float>::min();  // 0 is a slab of no thickness
    if (auto v = material.member("thickness")) {
        if (isTextureValue(*v))
            context.textures.push_back(
                {readTexture(*v, context.folder, 0.0f, std::numeric_limits<float>::max()),
                 [](MaterialModel& m, Rgb c) {
                     std::get<LayeredBsdf>(m).thickness = std::max(c.r, kThinnest);
                 }});
        else
            layered.thickness = std::max(v->numberAtLeast(0.0f), kThinnest);
    }
    if (auto v = material.member("medium_albedo"))
        layered.albedo = readColorParameter(
            *v, 0.0f, 1.0f, layered.albedo, context,
            [](MaterialModel& m, Rgb c) { std::get<LayeredBsdf>(m).albedo = clampedColor(c); });
    if (auto v = material.member("g")) layered.g = v->numberInRange(-0.999f, 0.999f);
    if (auto v = material.member("max_depth")) layered.maxDepth = int(v->integer(1, 1000));
    if (auto v = material.member("samples")) layered.samples = int(v->integer(1, 256));
}

// The coat of a layered material: "eta" and the roughness keys (smooth without them).
void readLayeredCoat(const JsonValue& material, MaterialContext& context, LayeredBsdf& layered) {
    if (auto v = material.member("eta")) layered.eta = v->numberAbove(0.0f);
    bool texturedRoughness = false;
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material, &texturedRoughness);
    if (texturedRoughness) addTexturedRoughness<layeredCoatDistribution>(material, context);
    if (distribution && (texturedRoughness || !isSmooth(distribution)))
        layered.coatDistribution = clampedForRendering(*distribution);
}

// "coated_diffuse": a Lambertian "albedo" under a dielectric coat ("eta", roughness). Its
// "model" is "analytic" (the default: materials/coated_diffuse.h, one closed form) or "layered"
// (pbrt-v4's coateddiffuse: materials/layered_bsdf.h, a random walk between the interfaces, with
// the slab's keys).
Material readCoatedDiffuse(const JsonValue& material, MaterialContext& context) {
    const bool layered =
        material.member("model") && material.member("model")->choice({"analytic", "layered"}) == 1;
    if (!layered)
        for (const std::string_view key : kLayeredSlabKeys)
            if (auto v = material.member(key))
                v->fail(fmt::format("\"{}\" is a key of the layered model: add \"model\": \"layered\"", key));
    if (layered) {
        LayeredBsdf model;
        if (auto v = material.member("albedo"))
            model.baseAlbedo = readColorParameter(
                *v, 0.0f, 1.0f, model.baseAlbedo, context,
                [](MaterialModel& m, Rgb c) { std::get<LayeredBsdf>(m).baseAlbedo = clampedColor(c); });
        readLayeredCoat(material, context, model);
        readLayeredSlab(material, context, model);
        return Material(model, readTwoSided(material), std::move(context.textures));
    }
    float eta = 1.5f;
    if (auto v = material.member("eta")) eta = v->numberAbove(0.0f);
    bool texturedRoughness = false;
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material, &texturedRoughness);
    const bool smooth = isSmooth(distribution) && !texturedRoughness;
    Rgb albedo(0.5f);
    if (auto v = material.member("albedo"))
        albedo = smooth ? readColorParameter(*v, 0.0f, 1.0f, albedo, context,
                                             [](MaterialModel& m, Rgb c) {
                                                 std::get<CoatedDiffuse>(m).albedo = clampedColor(c);
                                             })
                        : readColorParameter(*v, 0.0f, 1.0f, albedo, context, [](MaterialModel& m, Rgb c) {
                              std::get<RoughCoatedDiffuse>(m).albedo = clampedColor(c);
                          });
    if (smooth)
        return Material(CoatedDiffuse::make(albedo, eta), readTwoSided(material),
                        std::move(context.textures));
    if (texturedRoughness) addTexturedRoughness<distributionIn<RoughCoatedDiffuse>>(material, context);
    return Material(RoughCoatedDiffuse::make(albedo, eta, clampedForRendering(*distribution)),
                    readTwoSided(material), std::move(context.textures));
}

// "coated_conductor" (pbrt-v4's coatedconductor, materials/layered_bsdf.h): a dielectric coat
// ("eta", roughness) over the metal "conductor" ({"eta", "k"} or {"reflectance"}, relative to the
// outside, and its own roughness keys), with the slab's keys. Two-sided.
Material readCoatedConductor(const JsonValue& material, MaterialContext& context) {
    LayeredBsdf model;
    model.base = LayeredBsdf::Base::Conductor;
    readLayeredCoat(material, context, model);
    const JsonObject conductor(
        material.requiredMember("conductor"),
        {"eta", "k", "reflectance", "roughness", "roughness_mapping", "alpha", "distribution"});
    const ConductorSetters setters{[](MaterialModel& m, Rgb r) {
                                       std::get<LayeredBsdf>(m).conductorEta = Rgb(1.0f);
                                       std::get<LayeredBsdf>(m).conductorK = conductorKForReflectance(r);
                                   },
                                   [](MaterialModel& m, Rgb eta) {
                                       std::get<LayeredBsdf>(m).conductorEta = {std::max(eta.r, 1e-4f),
                                                                                std::max(eta.g, 1e-4f),
                                                                                std::max(eta.b, 1e-4f)};
                                   },
                                   [](MaterialModel& m, Rgb k) {
                                       std::get<LayeredBsdf>(m).conductorK = {
                                           std::max(k.r, 0.0f), std::max(k.g, 0.0f), std::max(k.b, 0.0f)};
                                   }};
    std::tie(model.conductorEta, model.conductorK) = readConductorIndex(conductor.value(), context, setters);
    bool texturedRoughness = false;
    const std::optional<MicrofacetDistribution> distribution =
        readDistribution(conductor.value(), &texturedRoughness);
    if (texturedRoughness) addTexturedRoughness<layeredConductorDistribution>(conductor.value(), context);
    if (distribution && (texturedRoughness || !isSmooth(distribution)))
        model.conductorDistribution = clampedForRendering(*distribution);
    readLayeredSlab(material, context, model);
    return Material(model, true, std::move(context.textures));
}

Material readInterface(const JsonValue&, MaterialContext&) { return Material(Interface{}); }

// "measured": a measured BRDF of the RGL database, "filename" naming its .bsdf file (spectral or
// RGB) relative to the scene file (materials/measured_bsdf.h).
Material readMeasured(const JsonValue& material, MaterialContext& context) {
    const std::filesystem::path path = std::filesystem::weakly_canonical(
        material.requiredMember("filename").existingFile(context.folder, "measured BRDF"));
    std::shared_ptr<const MeasuredBrdfTables>& tables = context.measuredFiles[path];
    if (!tables) tables = readMeasuredBsdf(path);
    return Material(MeasuredBsdf{tables}, readTwoSided(material), std::move(context.textures));
}

// Where a texture of a subsurface material's interior writes its value (TexturedInterior).
template <class Boundary>
TexturedInterior& texturedInteriorOf(MaterialModel& m) {
    return std::get<Boundary>(m).interior;
}
template <class Boundary>
struct InteriorSetters {
    static void sigmaA(MaterialModel& m, Rgb c) {
        texturedInteriorOf<Boundary>(m).sigmaA = clampedColor(c, kMax);
    }
    static void sigmaS(MaterialModel& m, Rgb c) {
        texturedInteriorOf<Boundary>(m).sigmaS = clampedColor(c, kMax);
    }
    static void reflectance(MaterialModel& m, Rgb c) {
        texturedInteriorOf<Boundary>(m).reflectance = clampedColor(c);
    }
    static void meanFreePath(MaterialModel& m, Rgb c) {
        texturedInteriorOf<Boundary>(m).meanFreePath = clampedColor(c, kMax);
    }
    static constexpr float kMax = std::numeric_limits<float>::max();
};

// pbrt-v4's default coefficients of a subsurface material given none (mm^-1, a milk).
constexpr Rgb kDefaultSubsurfaceSigmaA{0.0011f, 0.0024f, 0.014f};
constexpr Rgb kDefaultSubsurfaceSigmaS{2.55f, 3.21f, 3.77f};

// "subsurface": a dielectric boundary ("eta", default 1.33 as pbrt-v4's, and the rough
// dielectric's roughness keys) around a homogeneous medium that fills the shapes using it, in
// which light that enters scatters by the volumetric integrator's random walk. The medium is
// "sigma_a" and "sigma_s" or a "preset", times "scale", with "g" (readHomogeneousMedium), or
// "reflectance" (the diffuse reflectance asked for, a colour in [0, 1]) and "mfp" (its mean free
// path 1 / sigma_t, a colour > 0, default 1) times "scale" (materials/subsurface_albedo.h; with
// g != 0 the similarity relation sigma_s (1 - g) keeps the reduced albedo); pbrt-v4's milk-like
// coefficients when none is given. "sigma_a", "sigma_s", "reflectance" and "mfp" may be textures:
// a walk then takes the coefficients at the point where it enters (materials/subsurface_boundary.h).
Material readSubsurface(const JsonValue& material, MaterialContext& context) {
    const auto reflectance = material.member("reflectance"), mfp = material.member("mfp");
    const auto sigmaA = material.member("sigma_a"), sigmaS = material.member("sigma_s");
    const auto preset = material.member("preset");
    if (int(bool(reflectance)) + int(sigmaA || sigmaS) + int(bool(preset)) > 1)
        material.fail(
            "a subsurface medium is given one way: \"sigma_a\" and \"sigma_s\", a \"preset\", or "
            "\"reflectance\" and \"mfp\"");
    if (bool(sigmaA) != bool(sigmaS))
        material.fail("give both \"sigma_a\" and \"sigma_s\" (or a \"preset\", or \"reflectance\")");
    if (mfp && !reflectance) mfp->fail("\"mfp\" is the mean free path of a \"reflectance\": give one");
    const float eta = material.member("eta") ? material.member("eta")->numberAbove(0.0f) : 1.33f;
    bool texturedRoughness = false;
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material, &texturedRoughness);
    const bool smooth = isSmooth(distribution) && !texturedRoughness;
    auto textured = [](const std::optional<JsonValue>& v) { return v && isTextureValue(*v); };
    TexturedInterior interior;
    if (textured(sigmaA) || textured(sigmaS)) interior.kind = TexturedInterior::Kind::Coefficients;
    if (textured(reflectance) || textured(mfp)) interior.kind = TexturedInterior::Kind::Reflectance;

    // The medium: its phase function, and its coefficients where nothing is textured (the
    // textured ones read as 0 there; the walk takes the textures' values).
    Json constants = material.json();
    for (const char* key : {"sigma_a", "sigma_s"})
        if (constants.contains(key) && isTextureValue(*material.member(key))) constants[key] = 0;
    HomogeneousMedium medium =
        readHomogeneousMedium(JsonValue(constants, material.file(), material.pointer()));
    const float scale = material.member("scale") ? material.member("scale")->number() : 1.0f;
    interior.scale = scale;
    interior.g = medium.phase.g;
    const double internalReflectance = diffuseFresnelReflectance(1.0 / eta);  // a quadrature: once
    interior.internalReflectance = float(internalReflectance);
    auto setters = [&]<class Boundary>() {
        using S = InteriorSetters<Boundary>;
        const float largest = std::numeric_limits<float>::max();
        if (interior.kind == TexturedInterior::Kind::Coefficients) {
            interior.sigmaA = readColorParameter(*sigmaA, 0.0f, largest, Rgb(0.0f), context, S::sigmaA);
            interior.sigmaS = readColorParameter(*sigmaS, 0.0f, largest, Rgb(0.0f), context, S::sigmaS);
        } else if (interior.kind == TexturedInterior::Kind::Reflectance) {
            interior.reflectance =
                readColorParameter(*reflectance, 0.0f, 1.0f, Rgb(0.0f), context, S::reflectance);
            if (mfp)
                interior.meanFreePath =
                    readColorParameter(*mfp, 0.0f, largest, Rgb(1.0f), context, S::meanFreePath);
        }
    };
    if (smooth)
        setters.template operator()<SubsurfaceBoundary<Dielectric>>();
    else
        setters.template operator()<SubsurfaceBoundary<RoughDielectric>>();

    if (reflectance && !textured(reflectance) && !textured(mfp)) {
        const Rgb albedoAsked = reflectance->rgb(0.0f, 1.0f);
        const Rgb freePath = mfp ? mfp->rgb(0.0f) : Rgb(1.0f);
        float absorption[3], scattering[3];
        for (int c = 0; c < 3; ++c) {
            const double length = double(freePath[c]) * scale;
            if (!(length > 0.0) || !std::isfinite(1.0 / length))
                (mfp ? *mfp : material)
                    .fail("the mean free path times scale must be > 0 and its inverse fit a 32-bit float");
            const SubsurfaceCoefficients k = coefficientsForDiffuseReflectance(
                albedoAsked[c], length, internalReflectance, double(medium.phase.g));
            absorption[c] = float(k.sigmaA);
            scattering[c] = float(k.sigmaS);
        }
        medium.sigmaA = {absorption[0], absorption[1], absorption[2]};
        medium.sigmaS = {scattering[0], scattering[1], scattering[2]};
        if (!(medium.sigmaA + medium.sigmaS).isFinite())
            material.fail(
                "the coefficients of this reflectance and mean free path do not fit a 32-bit float");
    } else if (!sigmaA && !preset && !reflectance) {
        medium.sigmaA = kDefaultSubsurfaceSigmaA * scale;
        medium.sigmaS = kDefaultSubsurfaceSigmaS * scale;
        if (!(medium.sigmaA + medium.sigmaS).isFinite())
            material.fail("the default coefficients times scale do not fit a 32-bit float");
    }
    context.interior = medium;

    if (smooth)
        return Material(SubsurfaceBoundary<Dielectric>{Dielectric{eta}, interior}, true,
                        std::move(context.textures));
    if (texturedRoughness)
        addTexturedRoughness<distributionIn<SubsurfaceBoundary<RoughDielectric>>>(material, context);
    RoughDielectric rough;
    rough.eta = eta;
    rough.distribution = clampedForRendering(*distribution);
    return Material(SubsurfaceBoundary<RoughDielectric>{rough, interior}, true, std::move(context.textures));
}

// "bump": a height field in scene units along the normal (a number, or a texture whose first
// channel is read); "normal_map": a tangent-space normal map, a texture whose image is read as linear
// RGB (materials/normal_perturbation.h). At most one of them.
std::optional<NormalPerturbation> readNormalPerturbation(const JsonValue& material,
                                                         const std::filesystem::path& folder) {
    const auto bump = material.member("bump"), normalMap = material.member("normal_map");
    if (bump && normalMap) normalMap->fail("a material takes \"bump\" or \"normal_map\", not both");
    const float largest = std::numeric_limits<float>::max();
    if (bump) {
        if (!isTextureValue(*bump)) {
            bump->number();
            return std::nullopt;  // a constant height turns nothing
        }
        return NormalPerturbation{NormalPerturbation::Kind::Bump,
                                  readTexture(*bump, folder, -largest, largest)};
    }
    if (normalMap) {
        if (!isTextureValue(*normalMap))
            normalMap->failExpected("a texture (an image of tangent-space normals)");
        // Normals are data, not colours: an image is read as linear unless it says otherwise.
        Json linear = normalMap->json();
        if (linear.value("type", "") == "image" && !linear.contains("color_space"))
            linear["color_space"] = "linear";
        const JsonValue value(linear, normalMap->file(), normalMap->pointer());
        return NormalPerturbation{NormalPerturbation::Kind::NormalMap,
                                  readTexture(value, folder, 0.0f, 1.0f)};
    }
    return std::nullopt;
}

using MaterialReader = Material (*)(const JsonValue&, MaterialContext&);

// "diffuse_transmission": reflectance and transmittance, each a colour in [0, 1] or a texture
// (pbrt-v4's defaults, 0.25 each).
Material readDiffuseTransmission(const JsonValue& material, MaterialContext& context) {
    DiffuseTransmission model;
    if (auto v = material.member("reflectance"))
        model.reflectance = readColorParameter(
            *v, 0.0f, 1.0f, model.reflectance, context,
            [](MaterialModel& m, Rgb c) { std::get<DiffuseTransmission>(m).reflectance = clampedColor(c); });
    if (auto v = material.member("transmittance"))
        model.transmittance =
            readColorParameter(*v, 0.0f, 1.0f, model.transmittance, context, [](MaterialModel& m, Rgb c) {
                std::get<DiffuseTransmission>(m).transmittance = clampedColor(c);
            });
    return Material(model, true, std::move(context.textures));
}

// "hair": a fiber (materials/hair_bsdf.h, pbrt-v4's `hair`), shading curves. Its absorption is
// given as "sigma_a" (per unit of the fiber's diameter), as the "color" it should look (Chiang et
// al.'s inversion for its beta_n), or as melanin concentrations "eumelanin" and "pheomelanin" (one
// of the three; pbrt-v4's default, eumelanin 1.3, is brown hair); "eta" (1.55), "beta_m" and
// "beta_n" (0.3: longitudinal and azimuthal roughness) and "alpha" (2: the scales' tilt in degrees).
Material readHair(const JsonValue& material, MaterialContext&) {
    HairBsdf model;
    if (auto v = material.member("eta")) model.eta = v->numberAbove(0.0f);
    if (auto v = material.member("beta_m")) model.betaM = v->numberInRange(0.0f, 1.0f);
    if (auto v = material.member("beta_n")) model.betaN = v->numberInRange(0.0f, 1.0f);
    if (auto v = material.member("alpha")) model.alphaDegrees = v->numberInRange(-90.0f, 90.0f);
    const auto sigmaA = material.member("sigma_a"), color = material.member("color");
    const auto eumelanin = material.member("eumelanin"), pheomelanin = material.member("pheomelanin");
    if (int(bool(sigmaA)) + int(bool(color)) + int(eumelanin || pheomelanin) > 1)
        material.fail("a hair's absorption is given one way: \"sigma_a\", \"color\" or the melanins");
    if (sigmaA) {
        model.sigmaA = sigmaA->rgb(0.0f);
    } else if (color) {
        model.sigmaA = HairBsdf::sigmaAFromReflectance(color->rgb(0.0f, 1.0f), model.betaN);
    } else {
        model.sigmaA =
            HairBsdf::sigmaAFromConcentration(eumelanin     ? eumelanin->numberAtLeast(0.0f)
                                              : pheomelanin ? 0.0f
                                                            : 1.3f,
                                              pheomelanin ? pheomelanin->numberAtLeast(0.0f) : 0.0f);
    }
    return Material(model, true);
}

// "mix": read by readMix once every material is named; a placeholder until then.
Material readMixPlaceholder(const JsonValue&, MaterialContext&) { return Material::mixOf({}); }

const std::array<TypeRow<MaterialReader>, 16> kMaterialTypes{{
    {"lambert", {"type", "albedo", "two_sided", "bump", "normal_map"}, readLambert},
    {"phong", {"type", "diffuse", "specular", "exponent", "two_sided", "bump", "normal_map"}, readPhong},
    {"dielectric", {"type", "eta", "fresnel", "absorption", "bump", "normal_map"}, readDielectric},
    {"thin_dielectric", {"type", "eta", "fresnel", "bump", "normal_map"}, readThinDielectric},
    {"mirror", {"type", "tint", "two_sided", "bump", "normal_map"}, readMirror},
    {"conductor",
     {"type", "eta", "k", "reflectance", "tint", "two_sided", "bump", "normal_map"},
     readConductor},
    {"rough_conductor",
     {"type", "eta", "k", "reflectance", "tint", "roughness", "roughness_mapping", "alpha", "distribution",
      "two_sided", "bump", "normal_map"},
     readConductor},
    {"rough_dielectric",
     {"type", "eta", "fresnel", "absorption", "roughness", "roughness_mapping", "alpha", "distribution",
      "bump", "normal_map"},
     readDielectric},
    {"coated_diffuse",
     {"type", "albedo", "eta", "roughness", "roughness_mapping", "alpha", "distribution", "two_sided", "bump",
      "normal_map", "model", "thickness", "medium_albedo", "g", "max_depth", "samples"},
     readCoatedDiffuse},
    {"coated_conductor",
     {"type", "conductor", "eta", "roughness", "roughness_mapping", "alpha", "distribution", "bump",
      "normal_map", "thickness", "medium_albedo", "g", "max_depth", "samples"},
     readCoatedConductor},
    {"diffuse_transmission",
     {"type", "reflectance", "transmittance", "bump", "normal_map"},
     readDiffuseTransmission},
    {"hair",
     {"type", "sigma_a", "color", "eumelanin", "pheomelanin", "eta", "beta_m", "beta_n", "alpha"},
     readHair},
    {"subsurface",
     {"type", "eta", "roughness", "roughness_mapping", "alpha", "distribution", "sigma_a", "sigma_s",
      "preset", "reflectance", "mfp", "scale", "g", "bump", "normal_map"},
     readSubsurface},
    {"measured", {"type", "filename", "two_sided", "bump", "normal_map"}, readMeasured},
    {"interface", {"type"}, readInterface},
    {"mix", {"type", "materials", "amount"}, readMixPlaceholder},
}};

// {"type": "mix", "materials": [a, b], "amount": number in [0, 1] or texture (default 0.5)}:
// materials[index] becomes the mix, its two names resolved among all the scene's materials.
void readMix(const JsonValue& value, uint32_t index, const std::filesystem::path& folder,
             std::vector<Material>& materials, const std::vector<std::string>& names,
             const std::vector<MaterialInterior>& interiors) {
    const JsonValue pair = value.requiredMember("materials");
    if (!pair.json().is_array() || pair.arraySize() != 2) pair.failExpected("an array of two material names");
    MaterialMix mix;
    mix.first = readMaterialReference(pair.element(0), names);
    mix.second = readMaterialReference(pair.element(1), names);
    for (size_t k = 0; k < 2; ++k)
        if (materials[k == 0 ? mix.first : mix.second].isInterface())
            pair.element(k).fail("a mix cannot include an interface (a medium boundary is not a surface)");
    for (size_t k = 0; k < 2; ++k)
        for (const MaterialInterior& interior : interiors)
            if (interior.material == (k == 0 ? mix.first : mix.second))
                pair.element(k).fail(
                    "a mix cannot include a subsurface material (its medium fills the whole shape, which a "
                    "choice per shading point cannot give)");
    if (auto v = value.member("amount")) {
        if (isTextureValue(*v))
            mix.amountTexture = std::make_shared<const Texture>(readTexture(*v, folder, 0.0f, 1.0f));
        else
            mix.amount = v->numberInRange(0.0f, 1.0f);
    }
    materials[index] = Material::mixOf(std::move(mix));
}

// A mix that contains itself, through other mixes, would never resolve to a material: a
// depth-first search over the mixes (each visited once) finds such a cycle.
void refuseMixCycles(const JsonValue& section, const std::vector<Material>& materials,
                     const std::vector<std::string>& names) {
    enum class State : uint8_t { New, OnPath, Done };
    std::vector<State> state(materials.size(), State::New);
    for (uint32_t start = 0; start < materials.size(); ++start) {
        if (!materials[start].mix() || state[start] != State::New) continue;
        std::vector<std::pair<uint32_t, int>> path{{start, 0}};  // (material, its next branch)
        state[start] = State::OnPath;
        while (!path.empty()) {
            auto& [current, branch] = path.back();
            const MaterialMix* mix = materials[current].mix();
            if (branch == 2) {
                state[current] = State::Done;
                path.pop_back();
                continue;
            }
            const uint32_t next = branch++ == 0 ? mix->first : mix->second;
            if (!materials[next].mix() || state[next] == State::Done) continue;
            if (state[next] == State::OnPath) {
                std::string cycle;
                bool inCycle = false;
                for (const auto& [m, ignored] : path)
                    if ((inCycle = inCycle || m == next)) cycle += "\"" + names[m] + "\" -> ";
                section.member(names[next])
                    ->requiredMember("materials")
                    .fail(fmt::format("the mix contains itself: {}\"{}\"", cycle, names[next]));
            }
            state[next] = State::OnPath;
            path.push_back({next, 0});
        }
    }
}

}  // namespace

void readMaterials(const JsonValue& section, const std::filesystem::path& folder,
                   std::vector<Material>& materials, std::vector<std::string>& names,
                   std::vector<MaterialInterior>& interiors) {
    std::map<std::filesystem::path, std::shared_ptr<const MeasuredBrdfTables>> measuredFiles;
    for (const auto& [name, value] : section.members()) {
        MaterialContext context{folder, {}, {}, measuredFiles};
        Material material = findTypeRow<MaterialReader>(value, kMaterialTypes).read(value, context);
        if (auto perturbation = readNormalPerturbation(value, folder)) {
            std::vector<TexturedParameter> parameters;
            if (material.texturedParameters()) parameters = *material.texturedParameters();
            material = Material(material.model(), material.twoSided(), std::move(parameters),
                                std::move(perturbation));
        }
        if (context.interior) interiors.push_back({uint32_t(materials.size()), *context.interior});
        materials.push_back(std::move(material));
        names.push_back(name);
    }
    const uint32_t first = uint32_t(materials.size() - section.members().size());
    uint32_t index = first;
    for (const auto& [name, value] : section.members()) {
        if (value.requiredMember("type").string() == "mix")
            readMix(value, index, folder, materials, names, interiors);
        ++index;
    }
    refuseMixCycles(section, materials, names);
}

uint32_t readMaterialReference(const JsonValue& value, const std::vector<std::string>& names) {
    return readNameReference(value, names, "material", "materials");
}

}  // namespace penumbra
