#include "scenes/material_reader.h"

#include <fmt/format.h>

#include <array>
#include <cmath>

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

Material readDielectric(const JsonValue& material) {
    Dielectric dielectric;
    if (auto v = material.member("eta")) dielectric.eta = v->numberAbove(0.0f);
    if (auto v = material.member("fresnel")) dielectric.fresnel = readFresnel(*v);
    if (auto v = material.member("absorption")) dielectric.absorption = readAbsorption(*v);
    return Material(dielectric);
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

Material readConductor(const JsonValue& material) {
    Conductor conductor;
    const JsonValue etaValue = material.requiredMember("eta");
    conductor.eta = etaValue.rgb(0.0f);
    for (int c = 0; c < 3; ++c)
        if (!(conductor.eta[c] > 0.0f))
            etaValue.failExpected("a number or an array of 3 numbers (r, g, b), each > 0");
    conductor.k = material.requiredMember("k").rgb(0.0f);
    return Material(conductor, readTwoSided(material));
}

using MaterialReader = Material (*)(const JsonValue&);

const std::array<TypeRow<MaterialReader>, 6> kMaterialTypes{{
    {"lambert", {"type", "albedo", "two_sided"}, readLambert},
    {"phong", {"type", "diffuse", "specular", "exponent", "two_sided"}, readPhong},
    {"dielectric", {"type", "eta", "fresnel", "absorption"}, readDielectric},
    {"thin_dielectric", {"type", "eta", "fresnel"}, readThinDielectric},
    {"mirror", {"type", "tint", "two_sided"}, readMirror},
    {"conductor", {"type", "eta", "k", "two_sided"}, readConductor},
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
