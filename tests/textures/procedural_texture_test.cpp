// pbrt-v4's procedural and composite textures (textures/procedural_texture.h) against their
// definitions: scale, mix and direction mix of inputs, bilinear interpolation at its corners and
// centre, the 3D checkerboard's parity in its own space, the polka dots' geometry and coverage,
// fractal noise and turbulence as sums of octaves of core's noise, windy waves, the marble spline
// at its knots; the JSON reader's types and errors (nesting, and point textures refused where
// only (u, v) is known).
#include "textures/procedural_texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "core/hash.h"
#include "core/perlin_noise.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

float uniform(uint64_t index, uint64_t dimension) {
    return bitsToUnitFloat(uint32_t(hashWords(0x7e7, index, dimension) >> 32));
}

Texture procedural(ProceduralTexture texture) {
    return Texture::procedural(std::make_shared<const ProceduralTexture>(std::move(texture)));
}

TextureQuery queryAt(Vec2f uv, Vec3f p = {}, Vec3f n = {}) {
    TextureQuery query;
    query.uv = uv;
    query.p = p;
    query.n = n;
    return query;
}

void expectRgbNear(Rgb a, Rgb b, float tolerance) {
    EXPECT_NEAR(a.r, b.r, tolerance);
    EXPECT_NEAR(a.g, b.g, tolerance);
    EXPECT_NEAR(a.b, b.b, tolerance);
}

TEST(ProceduralTexture, ScaleAndMixCombineTheirInputs) {
    const Texture checker = Texture::checkerboard(Rgb(0.2f, 0.4f, 0.6f), Rgb(1.0f));
    ProceduralTexture scale;
    scale.kind = ProceduralKind::Scale;
    scale.inputs = {checker, Texture::constant(Rgb(1.5f))};
    const Texture scaled = procedural(scale);
    expectRgbNear(scaled.evaluate(queryAt({0.5f, 0.5f})), Rgb(0.3f, 0.6f, 0.9f), 1e-6f);
    expectRgbNear(scaled.evaluate(queryAt({1.5f, 0.5f})), Rgb(1.5f), 1e-6f);

    // A mix whose amount is itself a checkerboard (0.25 on even squares, 1 on odd ones).
    ProceduralTexture mix;
    mix.kind = ProceduralKind::Mix;
    mix.inputs = {Texture::constant(Rgb(0.0f, 0.4f, 1.0f)), scaled,
                  Texture::checkerboard(Rgb(0.25f), Rgb(1.0f))};
    const Texture mixed = procedural(mix);
    expectRgbNear(mixed.evaluate(queryAt({0.5f, 0.5f})),
                  Rgb(0.0f, 0.4f, 1.0f) * 0.75f + Rgb(0.3f, 0.6f, 0.9f) * 0.25f, 1e-6f);
    expectRgbNear(mixed.evaluate(queryAt({1.5f, 0.5f})), Rgb(1.5f), 1e-6f);
    EXPECT_FALSE(mixed.isSpatial());
}

TEST(ProceduralTexture, ADirectionMixWeighsByTheNormalsCosine) {
    ProceduralTexture mix;
    mix.kind = ProceduralKind::DirectionMix;
    mix.inputs = {Texture::constant(Rgb(1.0f, 0.0f, 0.0f)), Texture::constant(Rgb(0.0f, 0.0f, 1.0f))};
    mix.direction = {0.0f, 1.0f, 0.0f};
    const Texture texture = procedural(mix);
    EXPECT_TRUE(texture.isSpatial());
    expectRgbNear(texture.evaluate(queryAt({}, {}, {0, 1, 0})), Rgb(1.0f, 0.0f, 0.0f), 1e-6f);
    expectRgbNear(texture.evaluate(queryAt({}, {}, {0, -1, 0})), Rgb(1.0f, 0.0f, 0.0f), 1e-6f);
    expectRgbNear(texture.evaluate(queryAt({}, {}, {1, 0, 0})), Rgb(0.0f, 0.0f, 1.0f), 1e-6f);
    const float c = std::cos(1.0f);
    expectRgbNear(texture.evaluate(queryAt({}, {}, {std::sin(1.0f), c, 0})), Rgb(c, 0.0f, 1.0f - c), 1e-6f);
}

TEST(ProceduralTexture, BilerpInterpolatesItsCorners) {
    ProceduralTexture bilerp;
    bilerp.kind = ProceduralKind::Bilerp;
    bilerp.corners = {Rgb(0.0f), Rgb(1.0f, 0.0f, 0.0f), Rgb(0.0f, 1.0f, 0.0f), Rgb(0.0f, 0.0f, 1.0f)};
    Texture texture = procedural(bilerp);
    texture.mapUv({2.0f, 2.0f}, {0.0f, 0.0f});  // (u, v) in [0, 0.5] covers the corners
    expectRgbNear(texture.evaluate(queryAt({0.0f, 0.0f})), Rgb(0.0f), 1e-6f);
    expectRgbNear(texture.evaluate(queryAt({0.5f, 0.0f})), Rgb(1.0f, 0.0f, 0.0f), 1e-6f);
    expectRgbNear(texture.evaluate(queryAt({0.0f, 0.5f})), Rgb(0.0f, 1.0f, 0.0f), 1e-6f);
    expectRgbNear(texture.evaluate(queryAt({0.5f, 0.5f})), Rgb(0.0f, 0.0f, 1.0f), 1e-6f);
    expectRgbNear(texture.evaluate(queryAt({0.25f, 0.25f})), Rgb(0.25f), 1e-6f);
}

TEST(ProceduralTexture, TheCheckerboard3DAlternatesInItsOwnSpace) {
    ProceduralTexture checker;
    checker.kind = ProceduralKind::Checkerboard3D;
    checker.inputs = {Texture::constant(Rgb(1.0f)), Texture::constant(Rgb(0.0f))};
    // Cells of side 2, shifted by 1 in x.
    checker.worldToTexture = (Transform::translate({1, 0, 0}) * Transform::scale({2, 2, 2})).inverse();
    const Texture texture = procedural(checker);
    for (int i = 0; i < 2000; ++i) {
        const Vec3f p{20.0f * uniform(i, 0) - 10.0f, 20.0f * uniform(i, 1) - 10.0f,
                      20.0f * uniform(i, 2) - 10.0f};
        const int parity =
            int(std::floor((p.x - 1.0f) / 2.0f)) + int(std::floor(p.y / 2.0f)) + int(std::floor(p.z / 2.0f));
        // Away from the cells' faces, where the transform's rounding could decide.
        const float frac[3] = {std::fmod(std::abs(p.x - 1.0f), 2.0f), std::fmod(std::abs(p.y), 2.0f),
                               std::fmod(std::abs(p.z), 2.0f)};
        bool nearFace = false;
        for (float f : frac) nearFace = nearFace || f < 1e-4f || f > 2.0f - 1e-4f;
        if (nearFace) continue;
        EXPECT_EQ(texture.evaluate(queryAt({}, p)).r, (parity & 1) == 0 ? 1.0f : 0.0f) << i;
    }
}

// Each dot is a disk of radius 0.35 about a centre at most 0.15 from its cell's integer point, so a
// point inside one is within 0.5 of an integer point in each coordinate, and about half the cells
// (those where the noise is positive) hold one: the covered fraction is about half of pi 0.35^2.
TEST(ProceduralTexture, PolkaDotsAreDisksInAboutHalfTheCells) {
    int inside = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const Vec2f st{100.0f * uniform(i, 0), 100.0f * uniform(i, 1)};
        if (!insidePolkaDot(st)) continue;
        ++inside;
        const float ds = st.x - std::round(st.x), dt = st.y - std::round(st.y);
        EXPECT_LE(std::sqrt(ds * ds + dt * dt), 0.35f + 0.15f * std::sqrt(2.0f) + 1e-5f);
    }
    const double fraction = double(inside) / n, disk = 3.14159265 * 0.35 * 0.35;
    EXPECT_GT(fraction, 0.3 * disk);
    EXPECT_LT(fraction, 0.7 * disk);
}

TEST(ProceduralTexture, NoiseTexturesAreSumsOfOctavesOfCoresNoise) {
    for (int i = 0; i < 200; ++i) {
        const Vec3f p{10.0f * uniform(i, 0), 10.0f * uniform(i, 1), 10.0f * uniform(i, 2)};
        const float n0 = perlinNoise(p), n1 = perlinNoise(p * 1.99f), n2 = perlinNoise(p * (1.99f * 1.99f));
        EXPECT_FLOAT_EQ(fractalNoise(p, 0.5f, 1), n0);
        EXPECT_NEAR(fractalNoise(p, 0.5f, 3), n0 + 0.5f * n1 + 0.25f * n2, 1e-6f);
        // Turbulence: |octaves| plus 0.2 times the next octave's weight.
        EXPECT_NEAR(turbulence(p, 0.4f, 2), std::abs(n0) + 0.4f * std::abs(n1) + 0.16f * 0.2f, 1e-6f);
        ProceduralTexture windy;
        windy.kind = ProceduralKind::Windy;
        EXPECT_NEAR(procedural(windy).evaluate(queryAt({}, p)).r,
                    std::abs(fractalNoise(p * 0.1f, 0.5f, 3)) * fractalNoise(p, 0.5f, 6), 1e-6f);
        ProceduralTexture fbm;
        fbm.kind = ProceduralKind::Fbm;
        fbm.octaves = 3;
        fbm.worldToTexture = Transform::scale({0.5f, 0.5f, 0.5f});
        EXPECT_NEAR(procedural(fbm).evaluate(queryAt({}, p * 2.0f)).r, fractalNoise(p, 0.5f, 3), 1e-6f);
    }
}

TEST(ProceduralTexture, MarblePassesThroughItsSplinesKnots) {
    // t = 0 and 1 are the spline's ends, (0.58, 0.58, 0.6) times 1.5; t = 1/2 the start of segment 3,
    // the grey 0.5 times 1.5.
    expectRgbNear(marbleColor(0.0f), Rgb(0.87f, 0.87f, 0.9f), 1e-6f);
    expectRgbNear(marbleColor(1.0f), Rgb(0.87f, 0.87f, 0.9f), 1e-6f);
    expectRgbNear(marbleColor(0.5f), Rgb(0.75f), 1e-6f);
    // Within the control colours' hull everywhere.
    for (int i = 0; i <= 100; ++i) {
        const Rgb c = marbleColor(float(i) / 100.0f);
        EXPECT_GE(c.b, 1.5f * 0.33f - 1e-6f);
        EXPECT_LE(c.b, 1.5f * 0.6f + 1e-6f);
    }
}

std::string textureScene(const std::string& albedo, const std::string& shapeExtra = "") {
    return R"({"materials": {"m": {"type": "lambert", "albedo": )" + albedo +
           R"(}}, "shapes": [{"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m")" +
           shapeExtra + "}]}";
}

TEST(ProceduralTexture, TheLoaderReadsEveryTypeAndNamesWhatIsWrong) {
    for (
        const std::string texture :
        {R"({"type": "scale", "texture": {"type": "checkerboard", "colors": [0, 1]}, "scale": 0.5})",
         R"({"type": "mix", "textures": [0.2, {"type": "fbm"}], "amount": {"type": "wrinkled", "octaves": 4}})",
         R"({"type": "direction_mix", "textures": [0.2, 0.8], "direction": [0, 0, 1]})",
         R"({"type": "bilerp", "values": [0, 0.5, 0.5, 1], "uv_scale": 2})",
         R"({"type": "dots", "inside": [1, 0, 0], "outside": 0.5, "uv_scale": 4})",
         R"({"type": "checkerboard_3d", "colors": [0.1, 0.9], "transform": [{"scale": 0.25}]})",
         R"({"type": "windy"})", R"({"type": "marble", "scale": 3, "variation": 0.5, "roughness": 0.6})"}) {
        const Scene scene = parseScene(textureScene(texture), "scene.json");
        EXPECT_TRUE(scene.materials[0].isTextured()) << texture;
    }
    // Nesting is bounded.
    std::string deep = "0.5";
    for (int i = 0; i < 20; ++i) deep = R"({"type": "scale", "scale": 1, "texture": )" + deep + "}";
    InputError e = catchInputError([&] { parseScene(textureScene(deep), "scene.json"); });
    EXPECT_CONTAINS(e.what(), "textures nest at most 16 deep");
    e = catchInputError(
        [] { parseScene(textureScene("0.5", R"(, "alpha": {"type": "fbm"})"), "scene.json"); });
    EXPECT_CONTAINS(e.what(), "/shapes/0/alpha");
    EXPECT_CONTAINS(e.what(), "of (u, v) only");
    e = catchInputError(
        [] { parseScene(textureScene(R"({"type": "mix", "textures": [0.2]})"), "scene.json"); });
    EXPECT_CONTAINS(e.what(), "/materials/m/albedo/textures");
    e = catchInputError([] { parseScene(textureScene(R"({"type": "fbm", "octaves": 40})"), "scene.json"); });
    EXPECT_CONTAINS(e.what(), "/materials/m/albedo/octaves");
}

}  // namespace
}  // namespace penumbra
