// The materials section of scene files: every material type and key is read, and every bad value
// is an InputError naming the material's JSON pointer, the field, and what was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

#include "materials/subsurface_albedo.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/rgl_bsdf_writer.h"

namespace penumbra {
namespace {

using testing::catchInputError;

Scene parseMaterials(const std::string& materialsJson) {
    return parseScene(R"({"materials": )" + materialsJson + "}", "s.json");
}

std::string errorOf(const std::string& materialsJson) {
    return catchInputError([&] { parseMaterials(materialsJson); }).what();
}

// "bump" (a texture of heights; a number is a flat height, which turns nothing) and "normal_map"
// on any material but the interface, one or the other.
TEST(MaterialLoader, BumpAndNormalMaps) {
    const Scene scene = parseMaterials(R"({
        "bumped": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": 0.3,
                   "bump": {"type": "checkerboard", "colors": [0, 0.01]}},
        "mapped": {"type": "lambert", "normal_map": {"type": "constant", "value": [0.5, 0.5, 1]}},
        "flat": {"type": "lambert", "bump": 0.2}})");
    ASSERT_NE(scene.materials[0].perturbation(), nullptr);
    EXPECT_EQ(scene.materials[0].perturbation()->kind, NormalPerturbation::Kind::Bump);
    EXPECT_TRUE(scene.materials[0].isTextured());
    ASSERT_NE(scene.materials[1].perturbation(), nullptr);
    EXPECT_EQ(scene.materials[1].perturbation()->kind, NormalPerturbation::Kind::NormalMap);
    EXPECT_EQ(scene.materials[2].perturbation(), nullptr);
    EXPECT_FALSE(scene.materials[2].isTextured());
    EXPECT_NE(errorOf(R"({"m": {"type": "lambert", "bump": {"type": "constant", "value": 0}, "normal_map":
                  {"type": "constant", "value": [0.5, 0.5, 1]}}})")
                  .find("/materials/m/normal_map: a material takes \"bump\" or \"normal_map\", not both"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"m": {"type": "lambert", "normal_map": 1}})")
                  .find("/materials/m/normal_map: expected a texture (an image of tangent-space normals)"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"m": {"type": "interface", "bump": 1}})").find("/materials/m/bump: unknown key"),
              std::string::npos);
}

TEST(MaterialLoader, ReadsEveryTypeAndKey) {
    const Scene scene = parseMaterials(R"({
        "matte": {"type": "lambert", "albedo": [0.1, 0.2, 0.3], "two_sided": false},
        "plastic": {"type": "phong", "diffuse": [0.5, 0.4, 0.3], "specular": [0.5, 0.6, 0.7], "exponent": 250},
        "glass": {"type": "dielectric", "eta": 1.5, "fresnel": "schlick",
                  "absorption": {"color": [0.5, 0.25, 1], "distance": 2}},
        "pane": {"type": "thin_dielectric", "eta": 1.52},
        "mirror": {"type": "mirror", "tint": [0.9, 0.8, 0.7], "two_sided": false},
        "gold": {"type": "conductor", "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603], "tint": [1, 0.9, 0.8]},
        "defaults": {"type": "phong"}
    })");
    ASSERT_EQ(scene.materials.size(), 7u);
    EXPECT_EQ(scene.materialNames,
              (std::vector<std::string>{"matte", "plastic", "glass", "pane", "mirror", "gold", "defaults"}));
    const Lambert& matte = std::get<Lambert>(scene.materials[0].model());
    EXPECT_EQ(matte.albedo, Rgb(0.1f, 0.2f, 0.3f));
    EXPECT_FALSE(scene.materials[0].twoSided());

    const Phong& plastic = std::get<Phong>(scene.materials[1].model());
    EXPECT_EQ(plastic.kd, Rgb(0.5f, 0.4f, 0.3f));
    EXPECT_EQ(plastic.ks, Rgb(0.5f, 0.6f, 0.7f));
    EXPECT_EQ(plastic.exponent, 250.0f);
    EXPECT_TRUE(scene.materials[1].twoSided());  // the default

    const Dielectric& glass = std::get<Dielectric>(scene.materials[2].model());
    EXPECT_EQ(glass.eta, 1.5f);
    EXPECT_EQ(glass.fresnel, FresnelModel::Schlick);
    // Transmittance c after distance d: sigma = -ln(c) / d.
    EXPECT_NEAR(glass.absorption.r, std::log(2.0) / 2.0, 1e-6);
    EXPECT_NEAR(glass.absorption.g, std::log(4.0) / 2.0, 1e-6);
    EXPECT_EQ(glass.absorption.b, 0.0f);

    const ThinDielectric& pane = std::get<ThinDielectric>(scene.materials[3].model());
    EXPECT_EQ(pane.eta, 1.52f);
    EXPECT_EQ(pane.fresnel, FresnelModel::Exact);

    EXPECT_EQ(std::get<Mirror>(scene.materials[4].model()).tint, Rgb(0.9f, 0.8f, 0.7f));
    EXPECT_FALSE(scene.materials[4].twoSided());

    const Conductor& gold = std::get<Conductor>(scene.materials[5].model());
    EXPECT_EQ(gold.eta, Rgb(0.143f, 0.374f, 1.442f));
    EXPECT_EQ(gold.k, Rgb(3.983f, 2.385f, 1.603f));
    EXPECT_EQ(gold.tint, Rgb(1.0f, 0.9f, 0.8f));

    const Phong& defaults = std::get<Phong>(scene.materials[6].model());
    EXPECT_EQ(defaults.kd, Rgb(0.5f));
    EXPECT_EQ(defaults.ks, Rgb(0.0f));
    EXPECT_EQ(defaults.exponent, 10.0f);
}

// diffuse_transmission: reflectance and transmittance, constant or textured (clamped to [0, 1]).
TEST(MaterialLoader, DiffuseTransmission) {
    const Scene scene = parseMaterials(R"({
        "shade": {"type": "diffuse_transmission", "reflectance": 0.5, "transmittance": [0.1, 0.2, 0.3]},
        "leaf": {"type": "diffuse_transmission",
                 "transmittance": {"type": "checkerboard", "colors": [[0.2, 0.4, 0.1], 1]}},
        "defaults": {"type": "diffuse_transmission"}
    })");
    const auto& shade = std::get<DiffuseTransmission>(scene.materials[0].model());
    EXPECT_EQ(shade.reflectance, Rgb(0.5f));
    EXPECT_EQ(shade.transmittance, Rgb(0.1f, 0.2f, 0.3f));
    EXPECT_TRUE(any(scene.materials[0].flags() & BsdfFlags::Transmission));
    const auto& defaults = std::get<DiffuseTransmission>(scene.materials[2].model());
    EXPECT_EQ(defaults.reflectance, Rgb(0.25f));
    EXPECT_EQ(defaults.transmittance, Rgb(0.25f));
    ASSERT_TRUE(scene.materials[1].isTextured());
    TextureQuery query;
    query.uv = {1.5f, 0.5f};  // the odd square
    // at() makes a material of the values there: kept while its model is read.
    const Material odd = scene.materials[1].at(query);
    EXPECT_EQ(std::get<DiffuseTransmission>(odd.model()).transmittance, Rgb(1.0f));
    query.uv = {0.5f, 0.5f};
    const Material even = scene.materials[1].at(query);
    EXPECT_EQ(std::get<DiffuseTransmission>(even.model()).transmittance, Rgb(0.2f, 0.4f, 0.1f));
    const InputError e = testing::catchInputError(
        [] { parseMaterials(R"({"bad": {"type": "diffuse_transmission", "transmittance": 1.5}})"); });
    EXPECT_CONTAINS(e.what(), "/materials/bad/transmittance");
}

// "mix": two names (any order of definition), an amount or a texture; mixes of mixes; a cycle,
// an interface or a bad amount refused at the key that says so.
TEST(MaterialLoader, Mix) {
    const Scene scene = parseMaterials(R"({
        "both": {"type": "mix", "materials": ["red", "inner"], "amount": 0.25},
        "red": {"type": "lambert", "albedo": [0.8, 0.1, 0.1]},
        "inner": {"type": "mix", "materials": ["red", "blue"],
                  "amount": {"type": "checkerboard", "colors": [0, 1]}},
        "blue": {"type": "lambert", "albedo": [0.1, 0.1, 0.8]}
    })");
    const MaterialMix* both = scene.materials[0].mix();
    ASSERT_NE(both, nullptr);
    EXPECT_EQ(both->first, 1u);
    EXPECT_EQ(both->second, 2u);
    EXPECT_EQ(both->amount, 0.25f);
    const MaterialMix* inner = scene.materials[2].mix();
    ASSERT_NE(inner, nullptr);
    ASSERT_TRUE(inner->amountTexture);
    // The checkerboard's amount is 0 on even squares (red) and 1 on odd ones (blue), whatever the hash.
    for (int i = 0; i < 100; ++i) {
        const Vec3f p{0.01f * float(i), 0.5f, 0.0f};
        EXPECT_EQ(resolveMix(scene.materials, 2, p, {0, 0, 1}, {0.5f, 0.5f}), 1u);
        EXPECT_EQ(resolveMix(scene.materials, 2, p, {0, 0, 1}, {1.5f, 0.5f}), 3u);
        const uint32_t resolved = resolveMix(scene.materials, 0, p, {0, 0, 1}, {1.5f, 0.5f});
        EXPECT_TRUE(resolved == 1u || resolved == 3u);
    }

    // The message as a string: the exception, and the text what() points into, end with the call.
    auto error = [](const std::string& json) -> std::string {
        return testing::catchInputError([&] { parseMaterials(json); }).what();
    };
    EXPECT_CONTAINS(error(R"({"a": {"type": "mix", "materials": ["b", "c"]},
                              "b": {"type": "mix", "materials": ["c", "a"]},
                              "c": {"type": "lambert"}})"),
                    "the mix contains itself: \"a\" -> \"b\" -> \"a\"");
    EXPECT_CONTAINS(error(R"({"a": {"type": "mix", "materials": ["a", "a"]}})"), "/materials/a/materials");
    EXPECT_CONTAINS(error(R"({"a": {"type": "mix", "materials": ["c", "i"]}, "c": {"type": "lambert"},
                              "i": {"type": "interface"}})"),
                    "/materials/a/materials/1: a mix cannot include an interface");
    EXPECT_CONTAINS(error(R"({"a": {"type": "mix", "materials": ["c", "d"]}, "c": {"type": "lambert"}})"),
                    "/materials/a/materials/1");
    EXPECT_CONTAINS(error(R"({"a": {"type": "mix", "materials": ["c"]}, "c": {"type": "lambert"}})"),
                    "an array of two material names");
    EXPECT_CONTAINS(error(R"({"a": {"type": "mix", "materials": ["c", "c"], "amount": 2},
                              "c": {"type": "lambert"}})"),
                    "/materials/a/amount");
}

// The choice's frequency is the amount, at points and directions that differ in any bit.
TEST(MaterialMix, ChoosesTheSecondWithProbabilityAmount) {
    constexpr int kPoints = 400'000;
    for (float amount : {0.1f, 0.5f, 0.85f}) {
        const MaterialMix mix{0, 1, amount, nullptr};
        int second = 0;
        for (int i = 0; i < kPoints; ++i)
            second +=
                mix.choose({0.001f * float(i % 1000), 0.0f, 0.001f * float(i / 1000)}, {0.0f, 1.0f, 0.0f},
                           normalize(Vec3f{0.3f, 1.0f, 0.2f}), {0.0f, 0.0f}, 7) == 1;
        const double sigma = std::sqrt(amount * (1.0 - amount) / kPoints);
        EXPECT_NEAR(double(second) / kPoints, amount, 5.0 * sigma) << amount;
    }
    const MaterialMix none{4, 5, 0.0f, nullptr}, all{4, 5, 1.0f, nullptr};
    EXPECT_EQ(none.choose({1, 2, 3}, {0, 1, 0}, {0, 0, 1}, {}, 0), 4u);
    EXPECT_EQ(all.choose({1, 2, 3}, {0, 1, 0}, {0, 0, 1}, {}, 0), 5u);
}

// Flags, not hand lists, say what the integrator may do with each material.
TEST(MaterialFlags, DeriveSpecularityAndLobeChoice) {
    const Scene scene = parseMaterials(R"({
        "matte": {"type": "lambert"}, "plastic": {"type": "phong"}, "glass": {"type": "dielectric"},
        "pane": {"type": "thin_dielectric"}, "mirror": {"type": "mirror"},
        "gold": {"type": "conductor", "eta": 0.2, "k": 3},
        "brushed": {"type": "rough_conductor", "eta": 0.2, "k": 3, "roughness": 0.5},
        "frosted": {"type": "rough_dielectric", "roughness": 0.5},
        "varnish": {"type": "coated_diffuse"}, "satin": {"type": "coated_diffuse", "roughness": 0.5}
    })");
    const bool purelySpecular[] = {false, false, true, true, true, true, false, false, false, false};
    const bool severalLobes[] = {false, true, true, true, false, false, false, true, true, true};
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        EXPECT_EQ(scene.materials[i].isPurelySpecular(), purelySpecular[i]) << scene.materialNames[i];
        EXPECT_EQ(scene.materials[i].usesLobeSample(), severalLobes[i]) << scene.materialNames[i];
    }
}

// The rough materials: roughness r gives alpha = r^2, alpha is taken as it is, [u, v] is
// anisotropic, and below alpha 1e-3 (or without a roughness) the smooth model is used.
TEST(MaterialLoader, ReadsTheRoughMaterials) {
    const Scene scene = parseMaterials(R"({
        "brushed": {"type": "rough_conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1], "roughness": [0.2, 0.5]},
        "veach": {"type": "rough_conductor", "eta": 0.2, "k": 3.9, "alpha": 0.01, "two_sided": false,
                  "distribution": "beckmann", "tint": 0.3},
        "frosted": {"type": "rough_dielectric", "eta": 1.5, "roughness": 0.3,
                    "absorption": {"color": 0.5, "distance": 1}},
        "plastic": {"type": "coated_diffuse", "albedo": [0.7, 0.1, 0.1], "eta": 1.6, "alpha": 0.2},
        "varnish": {"type": "coated_diffuse", "albedo": 0.5},
        "polished": {"type": "rough_conductor", "eta": 0.2, "k": 3.9, "roughness": 0.03},
        "clear": {"type": "rough_dielectric", "eta": 1.33, "alpha": 0.0009}
    })");
    ASSERT_EQ(scene.materials.size(), 7u);
    const RoughConductor& brushed = std::get<RoughConductor>(scene.materials[0].model());
    EXPECT_FLOAT_EQ(brushed.distribution.alphaX, 0.04f);
    EXPECT_FLOAT_EQ(brushed.distribution.alphaY, 0.25f);
    EXPECT_EQ(brushed.k, Rgb(3.9f, 2.4f, 2.1f));
    const RoughConductor& veach = std::get<RoughConductor>(scene.materials[1].model());
    EXPECT_EQ(veach.distribution.alphaX, 0.01f);
    EXPECT_EQ(veach.distribution.kind, MicrofacetKind::Beckmann);
    EXPECT_EQ(veach.tint, Rgb(0.3f));
    EXPECT_EQ(brushed.distribution.kind, MicrofacetKind::Ggx);  // the default
    EXPECT_EQ(brushed.tint, Rgb(1.0f));
    EXPECT_FALSE(scene.materials[1].twoSided());
    const RoughDielectric& frosted = std::get<RoughDielectric>(scene.materials[2].model());
    EXPECT_FLOAT_EQ(frosted.distribution.alphaY, 0.09f);
    EXPECT_NEAR(frosted.absorption.g, std::log(2.0), 1e-6);
    EXPECT_NEAR(scene.materials[2].interiorAbsorption().r, std::log(2.0), 1e-6);
    const RoughCoatedDiffuse& plastic = std::get<RoughCoatedDiffuse>(scene.materials[3].model());
    EXPECT_EQ(plastic.albedo, Rgb(0.7f, 0.1f, 0.1f));
    EXPECT_EQ(plastic.eta, 1.6f);
    EXPECT_EQ(plastic.distribution.alphaX, 0.2f);
    EXPECT_NEAR(plastic.internalReflectance, diffuseFresnelReflectance(1.0 / 1.6), 1e-6);
    EXPECT_TRUE(std::holds_alternative<CoatedDiffuse>(scene.materials[4].model()));
    // roughness 0.03: alpha 9e-4 < 1e-3, as smooth as float can tell.
    EXPECT_TRUE(std::holds_alternative<Conductor>(scene.materials[5].model()));
    EXPECT_EQ(std::get<Dielectric>(scene.materials[6].model()).eta, 1.33f);
}

// "roughness_mapping": alpha = r^2 (the default), sqrt(r) (pbrt-v4's remaproughness) or r, for
// a constant roughness and a textured one alike (the texture's value at each point).
TEST(MaterialLoader, RoughnessMappings) {
    const Scene scene = parseMaterials(R"({
        "squared": {"type": "rough_conductor", "eta": 0.2, "k": 3.9, "roughness": 0.36},
        "sqrt": {"type": "rough_conductor", "eta": 0.2, "k": 3.9, "roughness": 0.36, "roughness_mapping": "sqrt"},
        "identity": {"type": "rough_dielectric", "roughness": [0.36, 0.16], "roughness_mapping": "identity"},
        "textured": {"type": "coated_diffuse", "roughness_mapping": "sqrt",
                     "roughness": {"type": "checkerboard", "colors": [0.36, 0.04]}},
        "glass": {"type": "rough_dielectric", "roughness_mapping": "identity",
                  "roughness": {"type": "checkerboard", "colors": [0.36, 0.04]}}
    })");
    EXPECT_FLOAT_EQ(std::get<RoughConductor>(scene.materials[0].model()).distribution.alphaX, 0.1296f);
    EXPECT_FLOAT_EQ(std::get<RoughConductor>(scene.materials[1].model()).distribution.alphaX, 0.6f);
    const MicrofacetDistribution& identity =
        std::get<RoughDielectric>(scene.materials[2].model()).distribution;
    EXPECT_FLOAT_EQ(identity.alphaX, 0.36f);
    EXPECT_FLOAT_EQ(identity.alphaY, 0.16f);
    TextureQuery even, odd;
    even.uv = {0.5f, 0.5f};
    odd.uv = {1.5f, 0.5f};
    EXPECT_FLOAT_EQ(std::get<RoughCoatedDiffuse>(scene.materials[3].at(even).model()).distribution.alphaX,
                    0.6f);
    EXPECT_FLOAT_EQ(std::get<RoughCoatedDiffuse>(scene.materials[3].at(odd).model()).distribution.alphaY,
                    0.2f);
    EXPECT_FLOAT_EQ(std::get<RoughDielectric>(scene.materials[4].at(odd).model()).distribution.alphaX, 0.04f);
    EXPECT_NE(
        errorOf(
            R"({"m": {"type": "rough_conductor", "eta": 1, "k": 1, "alpha": 0.1, "roughness_mapping": "sqrt"}})")
            .find("/materials/m/roughness_mapping"),
        std::string::npos);
    EXPECT_NE(
        errorOf(
            R"({"m": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": 0.1, "roughness_mapping": "cubed"}})")
            .find("/materials/m/roughness_mapping"),
        std::string::npos);
}

// "reflectance" instead of "eta" and "k" (pbrt-v4's artist-friendly conductor): eta 1 and the k
// whose Fresnel reflectance at normal incidence is that colour, a constant or a texture's value.
TEST(MaterialLoader, ConductorReflectance) {
    const Scene scene = parseMaterials(R"({
        "gold": {"type": "conductor", "reflectance": [0.9, 0.6, 0.2]},
        "worn": {"type": "rough_conductor", "roughness": 0.4,
                 "reflectance": {"type": "checkerboard", "colors": [0.3, 0.8]}}
    })");
    const Conductor& gold = std::get<Conductor>(scene.materials[0].model());
    EXPECT_EQ(gold.eta, Rgb(1.0f));
    const Rgb normal = gold.reflectance({0.0f, 0.0f, 1.0f});
    EXPECT_NEAR(normal.r, 0.9f, 1e-5f);
    EXPECT_NEAR(normal.g, 0.6f, 1e-5f);
    EXPECT_NEAR(normal.b, 0.2f, 1e-5f);
    TextureQuery even, odd;
    even.uv = {0.5f, 0.5f};
    odd.uv = {1.5f, 0.5f};
    for (const auto& [query, r] : {std::pair{even, 0.3f}, std::pair{odd, 0.8f}}) {
        const RoughConductor worn = std::get<RoughConductor>(scene.materials[1].at(query).model());
        EXPECT_EQ(worn.eta, Rgb(1.0f));
        EXPECT_NEAR(fresnelComplex(1.0f, worn.eta, worn.k).g, r, 1e-5f);
    }
    EXPECT_NE(errorOf(R"({"m": {"type": "conductor", "eta": 1, "k": 1, "reflectance": 0.5}})")
                  .find("/materials/m/reflectance: a conductor takes \"eta\" and \"k\", or \"reflectance\""),
              std::string::npos);
}

// A conductor's eta and k as textures, and a roughness textured per axis: [texture, texture] or
// [texture, number].
TEST(MaterialLoader, TexturedConductorIndicesAndRoughnessPerAxis) {
    const Scene scene = parseMaterials(R"({
        "patina": {"type": "conductor", "eta": {"type": "checkerboard", "colors": [0.2, [1, 2, 3]]},
                   "k": {"type": "checkerboard", "colors": [0, 4]}},
        "brushed": {"type": "rough_conductor", "eta": 1.5, "k": 2,
                    "roughness": [{"type": "checkerboard", "colors": [0.2, 0.6]}, 0.5]},
        "combed": {"type": "rough_dielectric", "eta": 1.5, "roughness_mapping": "identity",
                   "roughness": [{"type": "checkerboard", "colors": [0.2, 0.6]},
                                 {"type": "checkerboard", "colors": [0.7, 0.1]}]}
    })");
    TextureQuery even, odd;
    even.uv = {0.5f, 0.5f};
    odd.uv = {1.5f, 0.5f};
    const Conductor evenPatina = std::get<Conductor>(scene.materials[0].at(even).model());
    const Conductor oddPatina = std::get<Conductor>(scene.materials[0].at(odd).model());
    EXPECT_EQ(evenPatina.eta, Rgb(0.2f));
    EXPECT_EQ(evenPatina.k, Rgb(0.0f));
    EXPECT_EQ(oddPatina.eta, Rgb(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(oddPatina.k, Rgb(4.0f));
    const RoughConductor brushed = std::get<RoughConductor>(scene.materials[1].at(odd).model());
    EXPECT_FLOAT_EQ(brushed.distribution.alphaX, 0.36f);  // 0.6^2
    EXPECT_FLOAT_EQ(brushed.distribution.alphaY, 0.25f);  // 0.5^2
    const RoughDielectric evenCombed = std::get<RoughDielectric>(scene.materials[2].at(even).model());
    const RoughDielectric oddCombed = std::get<RoughDielectric>(scene.materials[2].at(odd).model());
    EXPECT_FLOAT_EQ(evenCombed.distribution.alphaX, 0.2f);
    EXPECT_FLOAT_EQ(evenCombed.distribution.alphaY, 0.7f);
    EXPECT_FLOAT_EQ(oddCombed.distribution.alphaX, 0.6f);
    EXPECT_FLOAT_EQ(oddCombed.distribution.alphaY, 0.1f);
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "rough_conductor", "eta": 1, "k": 1,
                                      "roughness": [{"type": "checkerboard", "colors": [0, 1]}, 2]}})"),
                    "/materials/m/roughness/1");
}

// "subsurface": a dielectric boundary (smooth or rough) and a medium that fills the shapes using
// it, given one of four ways; the medium added after the file's own, each shape's inside unless it
// names one.
TEST(MaterialLoader, SubsurfaceMaterials) {
    const Scene scene = parseScene(R"({
        "materials": {
            "skin": {"type": "subsurface", "preset": "Skin1", "scale": 10, "eta": 1.4},
            "wax": {"type": "subsurface", "sigma_a": [0.1, 0.2, 0.3], "sigma_s": 2, "g": 0.3, "roughness": 0.5},
            "jade": {"type": "subsurface", "reflectance": [0.2, 0.5, 0.9], "mfp": [1, 2, 4], "scale": 0.5},
            "milk": {"type": "subsurface"},
            "grey": {"type": "lambert"}},
        "media": {"fog": {"type": "homogeneous", "sigma_s": 0.1}},
        "shapes": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "skin"},
            {"type": "sphere", "center": [3, 0, 0], "radius": 1, "material": "wax", "outside": "fog"},
            {"type": "sphere", "center": [6, 0, 0], "radius": 1, "material": "jade", "inside": "fog"},
            {"type": "sphere", "center": [9, 0, 0], "radius": 1, "material": "grey"}]})",
                                   "s.json");
    ASSERT_EQ(scene.media.size(), 5u);
    EXPECT_EQ(scene.firstMaterialInterior, 1u);
    EXPECT_EQ(scene.mediumNames[1], "(inside of material \"skin\")");
    EXPECT_FALSE(scene.isMaterialInterior(0));
    EXPECT_TRUE(scene.isMaterialInterior(4));
    EXPECT_TRUE(std::holds_alternative<SubsurfaceBoundary<Dielectric>>(scene.materials[0].model()));
    EXPECT_FLOAT_EQ(std::get<SubsurfaceBoundary<Dielectric>>(scene.materials[0].model()).surface.eta, 1.4f);
    const auto& wax = std::get<SubsurfaceBoundary<RoughDielectric>>(scene.materials[1].model());
    EXPECT_FLOAT_EQ(wax.surface.eta, 1.33f);
    EXPECT_FLOAT_EQ(wax.surface.distribution.alphaX, 0.25f);
    // Skin1 (Jensen et al. 2001) in mm^-1, times 10.
    const auto& skin = std::get<HomogeneousMedium>(scene.media[1]);
    EXPECT_FLOAT_EQ(skin.sigmaA.b, 4.8f);
    EXPECT_FLOAT_EQ(skin.sigmaS.r, 7.4f);
    const auto& waxMedium = std::get<HomogeneousMedium>(scene.media[2]);
    EXPECT_FLOAT_EQ(waxMedium.sigmaA.g, 0.2f);
    EXPECT_FLOAT_EQ(waxMedium.sigmaS.b, 2.0f);
    EXPECT_FLOAT_EQ(waxMedium.phase.g, 0.3f);
    // reflectance and mfp: sigma_t = 1 / (mfp scale), and the albedo whose dipole reflectance under
    // eta 1.33 is the reflectance asked for.
    const auto& jade = std::get<HomogeneousMedium>(scene.media[3]);
    const double internal = diffuseFresnelReflectance(1.0 / 1.33);
    const double asked[3] = {0.2, 0.5, 0.9}, mfp[3] = {1, 2, 4};
    for (int c = 0; c < 3; ++c) {
        const double sigmaT = double(jade.sigmaA[c]) + double(jade.sigmaS[c]);
        EXPECT_NEAR(sigmaT, 1.0 / (0.5 * mfp[c]), 1e-6) << c;
        EXPECT_NEAR(dipoleDiffuseReflectance(double(jade.sigmaS[c]) / sigmaT, internal), asked[c], 1e-6) << c;
    }
    // pbrt-v4's default coefficients.
    EXPECT_FLOAT_EQ(std::get<HomogeneousMedium>(scene.media[4]).sigmaS.g, 3.21f);
    // The shapes: the interior inside unless the shape names one; the outside as named.
    EXPECT_EQ(scene.spheres[0].media.inside, 1u);
    EXPECT_EQ(scene.spheres[0].media.outside, MediumInterface::kVacuum);
    EXPECT_EQ(scene.spheres[1].media.inside, 2u);
    EXPECT_EQ(scene.spheres[1].media.outside, 0u);
    EXPECT_EQ(scene.spheres[2].media.inside, 0u);
    EXPECT_FALSE(scene.spheres[3].media.isTransition());
    EXPECT_TRUE(scene.hasMedia());

    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "sigma_a": 1}})"),
                    "/materials/m: give both \"sigma_a\" and \"sigma_s\"");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "preset": "Skin1", "reflectance": 0.5}})"),
                    "/materials/m: a subsurface medium is given one way");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "mfp": 1}})"),
                    "/materials/m/mfp: \"mfp\" is the mean free path of a \"reflectance\"");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "reflectance": 1.5}})"),
                    "/materials/m/reflectance");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "reflectance": 0.5, "mfp": 0}})"),
                    "/materials/m/mfp: the mean free path times scale must be > 0");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "preset": "Jelly"}})"), "/materials/m/preset");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "subsurface", "emission": 1}})"),
                    "/materials/m/emission: unknown key");
    EXPECT_CONTAINS(errorOf(R"({"s": {"type": "subsurface"}, "d": {"type": "lambert"},
                                "m": {"type": "mix", "materials": ["d", "s"]}})"),
                    "/materials/m/materials/1: a mix cannot include a subsurface material");
}

// A subsurface material's textured coefficients: written at each shading point into its boundary,
// whose walk takes them (sigma_a and sigma_s times scale; a reflectance inverted with its mfp).
TEST(MaterialLoader, TexturedSubsurfaceCoefficients) {
    const Scene scene = parseScene(R"({"materials": {
        "wax": {"type": "subsurface", "scale": 2,
                "sigma_a": {"type": "checkerboard", "colors": [0.1, 0.2]}, "sigma_s": [1, 2, 3]},
        "jade": {"type": "subsurface", "eta": 1.4, "roughness": 0.2, "g": 0.3,
                 "reflectance": {"type": "checkerboard", "colors": [0.3, 0.6]}, "mfp": 0.5},
        "plain": {"type": "subsurface", "sigma_a": 1, "sigma_s": 1}}})",
                                   "s.json");
    TextureQuery even, odd;
    even.uv = {0.5f, 0.5f};
    odd.uv = {1.5f, 0.5f};
    ASSERT_TRUE(scene.materials[0].isTextured());
    const auto waxEven = scene.materials[0].at(even).texturedInterior();
    const auto waxOdd = scene.materials[0].at(odd).texturedInterior();
    ASSERT_TRUE(waxEven && waxOdd);
    EXPECT_FLOAT_EQ(waxEven->first.g, 0.2f);
    EXPECT_FLOAT_EQ(waxOdd->first.g, 0.4f);
    EXPECT_EQ(waxEven->second, Rgb(2.0f, 4.0f, 6.0f));
    const auto jade = scene.materials[1].at(odd).texturedInterior();
    ASSERT_TRUE(jade);
    const SubsurfaceCoefficients k =
        coefficientsForDiffuseReflectance(0.6, 0.5, diffuseFresnelReflectance(1.0 / 1.4), 0.3);
    EXPECT_NEAR(jade->first.r, k.sigmaA, 1e-5 * k.sigmaA);
    EXPECT_NEAR(jade->second.b, k.sigmaS, 1e-5 * k.sigmaS);
    EXPECT_FALSE(scene.materials[2].texturedInterior());
    EXPECT_FALSE(scene.materials[2].isTextured());
}

// The layered materials (materials/layered_bsdf.h): "coated_conductor", and "coated_diffuse" with
// "model": "layered"; their values in the model, textures at each textured parameter, and errors.
TEST(MaterialLoader, LayeredMaterials) {
    const Scene scene = parseScene(R"({"materials": {
        "paint": {"type": "coated_conductor", "eta": 1.6, "roughness": 0.5,
                  "conductor": {"eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 1.8], "alpha": [0.1, 0.3]},
                  "thickness": 0.1, "medium_albedo": [0.5, 0.4, 0.3], "g": 0.2, "max_depth": 20, "samples": 4},
        "chrome": {"type": "coated_conductor", "conductor": {"reflectance": 0.9}},
        "plastic": {"type": "coated_diffuse", "model": "layered", "albedo": [0.1, 0.2, 0.3], "thickness": 0},
        "analytic": {"type": "coated_diffuse", "albedo": 0.4},
        "textured": {"type": "coated_conductor",
                     "roughness": {"type": "checkerboard", "colors": [0.1, 0.9]},
                     "conductor": {"reflectance": {"type": "checkerboard", "colors": [0.2, 0.8]},
                                   "roughness": {"type": "checkerboard", "colors": [0.3, 0.7]}},
                     "thickness": {"type": "checkerboard", "colors": [0.01, 2]},
                     "medium_albedo": {"type": "checkerboard", "colors": [0.25, 0.75]}}}})",
                                   "s.json");
    const auto& paint = std::get<LayeredBsdf>(scene.materials[0].model());
    EXPECT_EQ(paint.base, LayeredBsdf::Base::Conductor);
    EXPECT_FLOAT_EQ(paint.eta, 1.6f);
    EXPECT_FLOAT_EQ(paint.coatDistribution.alphaX, 0.25f);  // roughness^2
    EXPECT_EQ(paint.conductorEta, Rgb(0.2f, 0.9f, 1.1f));
    EXPECT_EQ(paint.conductorK, Rgb(3.9f, 2.4f, 1.8f));
    EXPECT_FLOAT_EQ(paint.conductorDistribution.alphaX, 0.1f);
    EXPECT_FLOAT_EQ(paint.conductorDistribution.alphaY, 0.3f);
    EXPECT_FLOAT_EQ(paint.thickness, 0.1f);
    EXPECT_EQ(paint.albedo, Rgb(0.5f, 0.4f, 0.3f));
    EXPECT_FLOAT_EQ(paint.g, 0.2f);
    EXPECT_EQ(paint.maxDepth, 20);
    EXPECT_EQ(paint.samples, 4);
    const auto& chrome = std::get<LayeredBsdf>(scene.materials[1].model());
    EXPECT_EQ(chrome.conductorEta, Rgb(1.0f));
    EXPECT_EQ(chrome.conductorK, conductorKForReflectance(Rgb(0.9f)));
    EXPECT_EQ(chrome.coatDistribution.alphaX, 0.0f);  // smooth: no roughness given
    EXPECT_FLOAT_EQ(chrome.eta, 1.5f);
    EXPECT_FLOAT_EQ(chrome.thickness, 0.01f);  // pbrt-v4's defaults
    EXPECT_EQ(chrome.maxDepth, 10);
    EXPECT_EQ(chrome.samples, 1);
    const auto& plastic = std::get<LayeredBsdf>(scene.materials[2].model());
    EXPECT_EQ(plastic.base, LayeredBsdf::Base::Diffuse);
    EXPECT_EQ(plastic.baseAlbedo, Rgb(0.1f, 0.2f, 0.3f));
    EXPECT_GT(plastic.thickness, 0.0f);  // 0: the thinnest slab
    EXPECT_TRUE(std::holds_alternative<CoatedDiffuse>(scene.materials[3].model()));
    // Each texture writes its parameter: at the checkerboards' two kinds of squares.
    const Material& textured = scene.materials[4];
    ASSERT_TRUE(textured.isTextured());
    EXPECT_EQ(textured.texturedParameters()->size(), 5u);
    TextureQuery even, odd;
    even.uv = {0.5f, 0.5f};
    odd.uv = {1.5f, 0.5f};
    const auto atEven = std::get<LayeredBsdf>(textured.at(even).model());
    const auto atOdd = std::get<LayeredBsdf>(textured.at(odd).model());
    EXPECT_FLOAT_EQ(atEven.coatDistribution.alphaX, 0.01f);
    EXPECT_FLOAT_EQ(atOdd.coatDistribution.alphaY, 0.81f);
    EXPECT_EQ(atEven.conductorK, conductorKForReflectance(Rgb(0.2f)));
    EXPECT_EQ(atOdd.conductorK, conductorKForReflectance(Rgb(0.8f)));
    EXPECT_FLOAT_EQ(atEven.conductorDistribution.alphaX, 0.09f);
    EXPECT_FLOAT_EQ(atOdd.conductorDistribution.alphaY, 0.49f);
    EXPECT_FLOAT_EQ(atEven.thickness, 0.01f);
    EXPECT_FLOAT_EQ(atOdd.thickness, 2.0f);
    EXPECT_EQ(atEven.albedo, Rgb(0.25f));
    EXPECT_EQ(atOdd.albedo, Rgb(0.75f));

    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_conductor"}})"),
                    "/materials/m: missing required key \"conductor\"");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_conductor", "conductor": {"eta": 1}}})"),
                    "/materials/m/conductor: missing required key \"k\"");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_conductor", "conductor": {"tint": 1}}})"),
                    "/materials/m/conductor/tint: unknown key");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_conductor", "conductor": {"reflectance": 0.5},
                                      "samples": 0}})"),
                    "/materials/m/samples");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_conductor", "conductor": {"reflectance": 0.5},
                                      "g": 1}})"),
                    "/materials/m/g");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_diffuse", "thickness": 0.1}})"),
                    "/materials/m/thickness: \"thickness\" is a key of the layered model: add \"model\": "
                    "\"layered\"");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "coated_diffuse", "model": "stochastic"}})"),
                    "/materials/m/model");
}

// "measured": a .bsdf file relative to the scene's folder, read once however many materials name
// it; a missing or malformed file is an error naming the file.
TEST(MaterialLoader, MeasuredMaterials) {
    const std::string folder = ::testing::TempDir();
    {
        std::ofstream out(folder + "/penumbra-loader-grey.bsdf", std::ios::binary);
        test::TabulationGrid grid;
        grid.thetaNodes = 4;
        grid.normalGrid = 8;
        grid.sampleGrid = 8;
        out << test::tabulateIsotropicGgxBrdf(
            0.5f, [](Vec3f, Vec3f wi) { return Rgb(0.3f * wi.z); }, grid);
        std::ofstream(folder + "/penumbra-loader-broken.bsdf", std::ios::binary)
            << std::string("tensor_file", 12);
    }
    const Scene scene = parseScene(R"({"materials": {
        "a": {"type": "measured", "filename": "penumbra-loader-grey.bsdf"},
        "b": {"type": "measured", "filename": "penumbra-loader-grey.bsdf", "two_sided": false}}})",
                                   folder + "/scene.json");
    const auto& a = std::get<MeasuredBsdf>(scene.materials[0].model());
    const auto& b = std::get<MeasuredBsdf>(scene.materials[1].model());
    EXPECT_EQ(a.tables, b.tables);  // read once
    EXPECT_EQ(a.tables->description, "a GGX BRDF tabulated by penumbra's tests");
    EXPECT_FALSE(scene.materials[1].twoSided());
    EXPECT_CONTAINS(catchInputError([&] {
                        parseScene(
                            R"({"materials": {"m": {"type": "measured", "filename": "nowhere.bsdf"}}})",
                            folder + "/scene.json");
                    }).what(),
                    "/materials/m/filename");
    EXPECT_CONTAINS(
        catchInputError([&] {
            parseScene(
                R"({"materials": {"m": {"type": "measured", "filename": "penumbra-loader-broken.bsdf"}}})",
                folder + "/scene.json");
        }).what(),
        "penumbra-loader-broken.bsdf: the header ends within the version");
    EXPECT_CONTAINS(errorOf(R"({"m": {"type": "measured"}})"), "/materials/m");
}

TEST(MaterialLoader, PhongEnergyConservation) {
    // kd + ks = 1 exactly is fine.
    EXPECT_NO_THROW(parseMaterials(R"({"p": {"type": "phong", "diffuse": 0.25, "specular": 0.75}})"));
    const std::string e =
        errorOf(R"({"p": {"type": "phong", "diffuse": [0.5, 0.5, 0.2], "specular": [0.5, 0.6, 0.1]}})");
    EXPECT_CONTAINS(e, "s.json: /materials/p/specular: diffuse + specular must not exceed 1");
    EXPECT_CONTAINS(e, "the green channel has 0.5 + 0.6 = 1.1");
    // The default diffuse (0.5) counts too.
    EXPECT_CONTAINS(errorOf(R"({"p": {"type": "phong", "specular": 0.9}})"),
                    "/materials/p/specular: diffuse + specular");
}

TEST(MaterialLoader, BadValuesNameThePointerAndTheField) {
    struct Case {
        const char* json;
        const char* message;
    };
    const Case cases[] = {
        {R"({"p": {"type": "phong", "exponent": -1}})",
         "/materials/p/exponent: expected a number >= 0, found -1"},
        {R"({"p": {"type": "phong", "diffuse": [0.5, -0.1, 0]}})",
         "/materials/p/diffuse/1: expected a number in [0, 1], found -0.1"},
        {R"({"p": {"type": "phong", "specular": 1.5}})",
         "/materials/p/specular: expected a number in [0, 1], found 1.5"},
        {R"({"p": {"type": "lambert", "albedo": 1.01}})",
         "/materials/p/albedo: expected a number in [0, 1], found 1.01"},
        {R"({"glass": {"type": "dielectric", "eta": 0}})",
         "/materials/glass/eta: expected a number > 0, found 0"},
        {R"({"glass": {"type": "dielectric", "eta": -1.5}})",
         "/materials/glass/eta: expected a number > 0, found -1.5"},
        {R"({"pane": {"type": "thin_dielectric", "eta": 0}})",
         "/materials/pane/eta: expected a number > 0, found 0"},
        {R"({"glass": {"type": "dielectric", "fresnel": "fast"}})",
         "/materials/glass/fresnel: expected one of: exact, schlick"},
        {R"({"glass": {"type": "dielectric", "absorption": {"color": [0.5, 1.2, 1], "distance": 1}}})",
         "/materials/glass/absorption/color/1: expected a number in [0, 1], found 1.2"},
        {R"({"glass": {"type": "dielectric", "absorption": {"color": [0.5, 0, 1], "distance": 1}}})",
         "/materials/glass/absorption/color: expected a transmittance in (0, 1] per channel"},
        {R"({"glass": {"type": "dielectric", "absorption": {"color": 0.5, "distance": 0}}})",
         "/materials/glass/absorption/distance: expected a number > 0, found 0"},
        {R"({"glass": {"type": "dielectric", "absorption": {"color": 0.5}}})",
         "/materials/glass/absorption: missing required key \"distance\""},
        {R"({"glass": {"type": "dielectric", "two_sided": true}})",
         "/materials/glass/two_sided: unknown key (expected one of: type, eta, fresnel, absorption, bump, "
         "normal_map)"},
        {R"({"pane": {"type": "thin_dielectric", "absorption": {"color": 0.5, "distance": 1}}})",
         "/materials/pane/absorption: unknown key (expected one of: type, eta, fresnel, bump, normal_map)"},
        {R"({"m": {"type": "mirror", "tint": [1, 1, 2]}})",
         "/materials/m/tint/2: expected a number in [0, 1], found 2"},
        {R"({"m": {"type": "mirror", "two_sided": 1}})",
         "/materials/m/two_sided: expected true or false, found 1"},
        {R"({"gold": {"type": "conductor", "eta": [0.1, 0, 1], "k": 1}})",
         "/materials/gold/eta: expected a number or an array of 3 numbers (r, g, b), each > 0"},
        {R"({"gold": {"type": "conductor", "eta": -1, "k": 1}})",
         "/materials/gold/eta: expected a number >= 0, found -1"},
        {R"({"gold": {"type": "conductor", "eta": 1, "k": [1, -2, 1]}})",
         "/materials/gold/k/1: expected a number >= 0, found -2"},
        {R"({"gold": {"type": "conductor", "eta": 1}})", "/materials/gold: missing required key \"k\""},
        {R"({"x": {"type": "plastic"}})",
         "/materials/x/type: expected one of: lambert, phong, dielectric, thin_dielectric, mirror, "
         "conductor, "
         "rough_conductor, rough_dielectric, coated_diffuse"},
        {R"({"x": {"albedo": 0.5}})", "/materials/x: missing required key \"type\""},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": 1.2}})",
         "/materials/r/roughness: expected a roughness in [0, 1] (alpha = roughness^2), found 1.2"},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": [0.1, -0.1]}})",
         "/materials/r/roughness/1: expected a roughness in [0, 1] (alpha = roughness^2), found -0.1"},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": [0.1, 0.2, 0.3]}})",
         "/materials/r/roughness: expected a number or an array of 2 numbers (along u, along v)"},
        {R"({"r": {"type": "rough_dielectric", "alpha": 0}})",
         "/materials/r/alpha: expected an alpha in (0, 4]"},
        {R"({"r": {"type": "rough_dielectric", "alpha": -0.5}})",
         "/materials/r/alpha: expected an alpha in (0, 4]"},
        {R"({"r": {"type": "rough_dielectric", "eta": 0, "roughness": 0.5}})",
         "/materials/r/eta: expected a number > 0, found 0"},
        {R"({"r": {"type": "coated_diffuse", "eta": -1}})",
         "/materials/r/eta: expected a number > 0, found -1"},
        {R"({"r": {"type": "coated_diffuse", "albedo": 1.2}})",
         "/materials/r/albedo: expected a number in [0, 1], found 1.2"},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "roughness": 0.5, "alpha": 0.2}})",
         "/materials/r/alpha: give either \"roughness\" or \"alpha\", not both"},
        {R"({"r": {"type": "coated_diffuse", "specular": 0.5}})",
         "/materials/r/specular: unknown key (expected one of: type, albedo, eta, roughness, "
         "roughness_mapping, alpha, distribution, two_sided, bump, normal_map, model, thickness, "
         "medium_albedo, g, "
         "max_depth, samples)"},
        {R"({"r": {"type": "conductor", "eta": 1, "k": 1, "roughness": 0.5}})",
         "/materials/r/roughness: unknown key (expected one of: type, eta, k, reflectance, tint, two_sided, "
         "bump, normal_map)"},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "alpha": 0.1, "distribution": "phong"}})",
         "/materials/r/distribution: expected one of: ggx, beckmann"},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "distribution": "beckmann"}})",
         "/materials/r/distribution: a distribution needs a \"roughness\" or an \"alpha\""},
        {R"({"r": {"type": "rough_conductor", "eta": 1, "k": 1, "tint": [1, 0.5, 1.5]}})",
         "/materials/r/tint/2: expected a number in [0, 1], found 1.5"},
    };
    for (const Case& c : cases)
        EXPECT_CONTAINS(errorOf(c.json), std::string("s.json: ") + c.message) << c.json;
}

}  // namespace
}  // namespace penumbra
