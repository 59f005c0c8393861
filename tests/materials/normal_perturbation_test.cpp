// Bump and normal maps (materials/normal_perturbation.h) against closed forms: a bump's forward
// difference across a checkerboard's edge turns the normal by atan(step / du), with du from the
// footprint or pbrt-v4's 0.0005 without one; a height that does not change turns nothing; a
// constant normal map tilts the normal by its angle in the dp/du direction; every result faces
// the geometric normal's side. And in a render: a Lambert plane under a directional light along
// its normal, its shading normal tilted by a normal map by alpha, reflects albedo / pi E cos(alpha),
// on both backends.
#include "materials/normal_perturbation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"

namespace penumbra {
namespace {

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

const Vec3f kUp{0.0f, 0.0f, 1.0f}, kDpdu{2.0f, 0.0f, 0.0f}, kDpdv{0.0f, 3.0f, 0.0f};

// Heights 0 and `step` in squares of side 1 in (u, v): the edge at u = 1 (for v in [0, 1)).
NormalPerturbation stepBump(float step) {
    return {NormalPerturbation::Kind::Bump, Texture::checkerboard(Rgb(0.0f), Rgb(step))};
}

TEST(NormalPerturbation, ABumpTurnsTheNormalByItsForwardDifference) {
    // Without a footprint du = 0.0005: at u = 0.9998 the step 0.001 lies within it, a slope of
    // 0.001 / 0.0005 = 2 along dp/du, whose length is 2: cross((2, 0, 2), (0, 3, 0)) ~ (-1, 0, 1).
    TextureQuery query;
    query.uv = {0.9998f, 0.5f};
    expectNear(perturbedNormal(stepBump(0.001f), query, kUp, kDpdu, kDpdv, kUp),
               normalize(Vec3f{-1.0f, 0.0f, 1.0f}));
    // Away from the edge the height is flat: the normal is kept.
    query.uv = {0.5f, 0.5f};
    expectNear(perturbedNormal(stepBump(0.001f), query, kUp, kDpdu, kDpdv, kUp), kUp);
    // With a footprint, du = (|du/dx| + |du/dy|) / 2 = 0.002: slope 0.5, normal ~ (-0.5, 0, 2).
    query.uv = {0.9995f, 0.5f};
    query.dudx = 0.003f, query.dudy = -0.001f;
    expectNear(perturbedNormal(stepBump(0.001f), query, kUp, kDpdu, kDpdv, kUp),
               normalize(Vec3f{-0.5f, 0.0f, 2.0f}));
    // Across the edge in v (at v = 0.9998, u in [0, 1)): slope 2 along dp/dv = (0, 3, 0):
    // cross((2, 0, 0), (0, 3, 2)) = (0, -4, 6).
    TextureQuery inV;
    inV.uv = {0.5f, 0.9998f};
    expectNear(perturbedNormal(stepBump(0.001f), inV, kUp, kDpdu, kDpdv, kUp),
               normalize(Vec3f{0.0f, -4.0f, 6.0f}));
}

TEST(NormalPerturbation, AConstantNormalMapTiltsTheNormalTowardsDpDu) {
    const float alpha = 0.6f;
    const NormalPerturbation map{
        NormalPerturbation::Kind::NormalMap,
        Texture::constant(Rgb(0.5f + 0.5f * std::sin(alpha), 0.5f, 0.5f + 0.5f * std::cos(alpha)))};
    TextureQuery query;
    query.uv = {0.3f, 0.7f};
    expectNear(perturbedNormal(map, query, kUp, kDpdu, kDpdv, kUp), {std::sin(alpha), 0.0f, std::cos(alpha)});
    // (0.5, 0.5, 1) is the unperturbed normal; a normal map pointing below the surface is turned to
    // the geometric normal's side.
    const NormalPerturbation flat{NormalPerturbation::Kind::NormalMap,
                                  Texture::constant(Rgb(0.5f, 0.5f, 1.0f))};
    expectNear(perturbedNormal(flat, query, kUp, kDpdu, kDpdv, kUp), kUp);
    const NormalPerturbation down{NormalPerturbation::Kind::NormalMap,
                                  Texture::constant(Rgb(0.5f, 0.5f, 0.0f))};
    expectNear(perturbedNormal(down, query, kUp, kDpdu, kDpdv, kUp), kUp);
}

TEST(NormalPerturbation, ANormalMappedPlaneUnderASunReflectsItsCosine) {
    const float alpha = 0.9f;  // 51.6 degrees
    const std::string scene = R"({
        "camera": {"look_from": [0, 0, 5], "look_at": [0, 0, 0], "fov": 10},
        "film": {"resolution": [8, 8], "spp": 4},
        "integrator": {"max_depth": 1},
        "materials": {"m": {"type": "lambert", "albedo": 0.5, "normal_map": {"type": "constant", "value": [)" +
                              std::to_string(0.5 + 0.5 * std::sin(alpha)) + ", 0.5, " +
                              std::to_string(0.5 + 0.5 * std::cos(alpha)) + R"(]}}},
        "shapes": [{"type": "quad", "corner": [-10, -10, 0], "edge1": [20, 0, 0], "edge2": [0, 20, 0], "material": "m"}],
        "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": 2}]})";
    const Scene parsed = parseScene(scene, "bumped.json");
    ASSERT_NE(parsed.materials[0].perturbation(), nullptr);
    // The values written with 6 decimals: the tilt they give, not alpha itself.
    const double s = 2.0 * std::stod(std::to_string(0.5 + 0.5 * std::sin(alpha))) - 1.0;
    const double c = 2.0 * std::stod(std::to_string(0.5 + 0.5 * std::cos(alpha))) - 1.0;
    const double expected = 0.5 / 3.14159265358979323846 * 2.0 * c / std::hypot(s, c);
    for (const AcceleratorKind accel : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        RenderOptions options;
        options.accelerator = accel;
        Film film(8, 8);
        render(parsed, options, film);
        // Every sample sees the plane lit along its normal: no noise, only float rounding.
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                EXPECT_NEAR(film.at(x, y).mean().r, expected, 1e-5 * expected) << x << "," << y;
    }
    // Without the map, albedo / pi E.
    const std::string plain = std::string(scene).replace(
        scene.find(", \"normal_map\""), scene.find("}}},") + 1 - scene.find(", \"normal_map\""), "");
    Film film(8, 8);
    render(parseScene(plain, "plain.json"), RenderOptions{}, film);
    EXPECT_NEAR(film.at(4, 4).mean().r, 0.5 / 3.14159265358979323846 * 2.0, 1e-6);
}

}  // namespace
}  // namespace penumbra
