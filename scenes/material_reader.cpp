#include "scenes/material_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "scenes/type_table.h"

namespace penumbra {

namespace {

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

Material readLambert(const JsonValue& material) {
    Lambert lambert;
    if (auto v = material.member("albedo")) lambert.albedo = v->rgb(0.0f, 1.0f);
    return Material(lambert, readTwoSided(material));
}

Material readPhong(const JsonValue& material) {
    Phong phong;
    if (auto v = material.member("diffuse")) phong.kd = v->rgb(0.0f, 1.0f);
    if (auto v = material.member("exponent")) phong.exponent = v->numberAtLeast(0.0f);
    const bool twoSided = readTwoSided(material);
    if (auto v = material.member("specular")) {
        phong.ks = v->rgb(0.0f, 1.0f);
        // diffuse alone is at most 1, so a sum above 1 always involves a given specular.
        static constexpr const char* kChannels[] = {"red", "green", "blue"};
        for (int c = 0; c < 3; ++c)
            if (phong.kd[c] + phong.ks[c] > 1.0f)
                v->fail(fmt::format(
                    "diffuse + specular must not exceed 1 in any channel (energy conservation), but "
                    "the {} channel has {} + {} = {}",
                    kChannels[c], phong.kd[c], phong.ks[c], phong.kd[c] + phong.ks[c]));
    }
    return Material(phong, twoSided);
}

Material readThinDielectric(const JsonValue& material) {
    ThinDielectric thin;
    if (auto v = material.member("eta")) thin.eta = v->numberAbove(0.0f);
    if (auto v = material.member("fresnel")) thin.fresnel = readFresnel(*v);
    return Material(thin);
}

Material readMirror(const JsonValue& material) {
    Mirror mirror;
    if (auto v = material.member("tint")) mirror.tint = v->rgb(0.0f, 1.0f);
    return Material(mirror, readTwoSided(material));
}


// A rough surface's microfacet distribution: "distribution" ("ggx" or "beckmann") and the slopes
// from "roughness" r in [0, 1] (alpha = r^2) or "alpha" > 0, each a number or [along u, along v]
// for an anisotropic surface; none when no roughness is given.
std::optional<MicrofacetDistribution> readDistribution(const JsonValue& material) {
    const auto roughness = material.member("roughness");
    const auto alpha = material.member("alpha");
    const auto kind = material.member("distribution");
    if (roughness && alpha) alpha->fail("give either \"roughness\" or \"alpha\", not both");
    if (!roughness && !alpha) {
        if (kind) kind->fail("a distribution needs a \"roughness\" or an \"alpha\"");
        return std::nullopt;
    }
    const JsonValue& value = roughness ? *roughness : *alpha;
    auto read = [&](const JsonValue& v) {
        if (roughness) {
            const float r = v.number();
            if (!(r >= 0.0f && r <= 1.0f)) v.failExpected("a roughness in [0, 1] (alpha = roughness^2)");
            return roughnessToAlpha(r);
        }
        const float a = v.number();
        if (!(a > 0.0f && a <= 4.0f)) v.failExpected("an alpha in (0, 4] (0 is a smooth surface: use the smooth material)");
        return a;
    };
    MicrofacetDistribution d;
    if (kind) d.kind = kind->choice({"ggx", "beckmann"}) == 0 ? MicrofacetKind::Ggx : MicrofacetKind::Beckmann;
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

// "conductor" and "rough_conductor" (whose table row also accepts the roughness keys).
Material readConductor(const JsonValue& material) {
    const Rgb eta = readConductorEta(material);
    const Rgb k = material.requiredMember("k").rgb(0.0f);
    Rgb tint(1.0f);
    if (auto v = material.member("tint")) tint = v->rgb(0.0f, 1.0f);
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material);
    if (isSmooth(distribution)) return Material(Conductor{eta, k, tint}, readTwoSided(material));
    return Material(RoughConductor{eta, k, clampedForRendering(*distribution), tint}, readTwoSided(material));
}

// "dielectric" and "rough_dielectric", likewise.
Material readDielectric(const JsonValue& material) {
    Dielectric smooth;
    if (auto v = material.member("eta")) smooth.eta = v->numberAbove(0.0f);
    if (auto v = material.member("fresnel")) smooth.fresnel = readFresnel(*v);
    if (auto v = material.member("absorption")) smooth.absorption = readAbsorption(*v);
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material);
    if (isSmooth(distribution)) return Material(smooth);
    return Material(RoughDielectric{smooth.eta, smooth.fresnel, smooth.absorption, clampedForRendering(*distribution)});
}

Material readCoatedDiffuse(const JsonValue& material) {
    Rgb albedo(0.5f);
    if (auto v = material.member("albedo")) albedo = v->rgb(0.0f, 1.0f);
    float eta = 1.5f;
    if (auto v = material.member("eta")) eta = v->numberAbove(0.0f);
    const std::optional<MicrofacetDistribution> distribution = readDistribution(material);
    if (isSmooth(distribution)) return Material(CoatedDiffuse::make(albedo, eta), readTwoSided(material));
    return Material(RoughCoatedDiffuse::make(albedo, eta, clampedForRendering(*distribution)), readTwoSided(material));
}

using MaterialReader = Material (*)(const JsonValue&);

const std::array<TypeRow<MaterialReader>, 9> kMaterialTypes{{
    {"lambert", {"type", "albedo", "two_sided"}, readLambert},
    {"phong", {"type", "diffuse", "specular", "exponent", "two_sided"}, readPhong},
    {"dielectric", {"type", "eta", "fresnel", "absorption"}, readDielectric},
    {"thin_dielectric", {"type", "eta", "fresnel"}, readThinDielectric},
    {"mirror", {"type", "tint", "two_sided"}, readMirror},
    {"conductor", {"type", "eta", "k", "tint", "two_sided"}, readConductor},
    {"rough_conductor", {"type", "eta", "k", "tint", "roughness", "alpha", "distribution", "two_sided"}, readConductor},
    {"rough_dielectric", {"type", "eta", "fresnel", "absorption", "roughness", "alpha", "distribution"}, readDielectric},
    {"coated_diffuse", {"type", "albedo", "eta", "roughness", "alpha", "distribution", "two_sided"}, readCoatedDiffuse},
}};

}  // namespace

void readMaterials(const JsonValue& section, std::vector<Material>& materials, std::vector<std::string>& names) {
    for (const auto& [name, value] : section.members()) {
        materials.push_back(findTypeRow<MaterialReader>(value, kMaterialTypes).read(value));
        names.push_back(name);
    }
}

uint32_t readMaterialReference(const JsonValue& value, const std::vector<std::string>& names) {
    const std::string name = value.string();
    std::string known;
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i] == name) return uint32_t(i);
        known += (known.empty() ? "" : ", ") + names[i];
    }
    value.fail(fmt::format("unknown material \"{}\" ({})", name,
                           known.empty() ? "the scene defines no materials" : "known materials: " + known));
}

}  // namespace penumbra
