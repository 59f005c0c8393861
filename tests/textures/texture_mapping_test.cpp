// The 2D textures' mappings (textures/texture_mapping.h) against their definitions: spherical,
// cylindrical and planar coordinates of known points, in a placed texture space; their footprint
// derivatives against finite differences; the (u, v) mapping unchanged; the JSON reader.
#include "textures/texture_mapping.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "core/transform.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"
#include "textures/texture.h"

namespace penumbra {
namespace {

// A query at the point p with footprint dpdx, dpdy (no (u, v): the mappings of the point ignore it).
TextureQuery at(Vec3f p, Vec3f dpdx = {}, Vec3f dpdy = {}) {
    return {
        .uv = {}, .p = p, .n = {}, .dudx = 0, .dvdx = 0, .dudy = 0, .dvdy = 0, .dpdx = dpdx, .dpdy = dpdy};
}

TextureMapping mappingOf(TextureMappingKind kind) {
    TextureMapping mapping;
    mapping.kind = kind;
    return mapping;
}

// pbrt-v4's SphericalMapping: s = theta / pi from +z, t = phi / 2 pi in [0, 1).
TEST(TextureMapping, SphericalCoordinatesOfKnownPoints) {
    const TextureMapping m = mappingOf(TextureMappingKind::Spherical);
    struct Case {
        Vec3f p;
        float s, t;
    } cases[] = {{{0, 0, 2}, 0.0f, 0.0f},
                 {{3, 0, 0}, 0.5f, 0.0f},
                 {{0, 1, 0}, 0.5f, 0.25f},
                 {{-1, 0, 0}, 0.5f, 0.5f},
                 {{0, -1, 0}, 0.5f, 0.75f},
                 {{0, 0, -1}, 1.0f, 0.0f},
                 {{1, 1, std::sqrt(2.0f)}, 0.25f, 0.125f}};
    for (const Case& c : cases) {
        const TextureCoordinates st = m.map(at(c.p));
        EXPECT_NEAR(st.st.x, c.s, 1e-6f) << c.p.x << " " << c.p.y << " " << c.p.z;
        EXPECT_NEAR(st.st.y, c.t, 1e-6f) << c.p.x << " " << c.p.y << " " << c.p.z;
    }
}

// pbrt-v4's CylindricalMapping: s = (pi + atan2(y, x)) / 2 pi, t = z.
TEST(TextureMapping, CylindricalAndPlanarCoordinatesOfKnownPoints) {
    const TextureMapping cylinder = mappingOf(TextureMappingKind::Cylindrical);
    EXPECT_NEAR(cylinder.map(at({1, 0, 5})).st.x, 0.5f, 1e-6f);
    EXPECT_FLOAT_EQ(cylinder.map(at({1, 0, 5})).st.y, 5.0f);
    EXPECT_NEAR(cylinder.map(at({0, 2, -1})).st.x, 0.75f, 1e-6f);
    EXPECT_NEAR(cylinder.map(at({0, -2, 0})).st.x, 0.25f, 1e-6f);
    TextureMapping plane = mappingOf(TextureMappingKind::Planar);
    plane.v1 = {1, 0, 0};
    plane.v2 = {0, 0.5f, 1};
    const TextureCoordinates c = plane.map(at({2, 3, 4}, {1, 0, 0}, {0, 2, 0}));
    EXPECT_FLOAT_EQ(c.st.x, 2.0f);
    EXPECT_FLOAT_EQ(c.st.y, 5.5f);
    EXPECT_FLOAT_EQ(c.dsdx, 1.0f);
    EXPECT_FLOAT_EQ(c.dtdy, 1.0f);
    EXPECT_FLOAT_EQ(c.dsdy, 0.0f);
}

// The texture's space placed in the world: a sphere mapping centred at (10, 0, 0), scaled by 2 and
// turned 90 degrees about x (its +z along the world's -y).
TEST(TextureMapping, TheTextureSpaceIsWhereItsTransformPlacesIt) {
    TextureMapping m = mappingOf(TextureMappingKind::Spherical);
    const Transform worldFromTexture =
        Transform::translate({10, 0, 0}) * Transform::rotate(90.0f, {1, 0, 0}) * Transform::scale({2, 2, 2});
    m.worldToTexture = worldFromTexture.inverse();
    EXPECT_NEAR(m.map(at({10, -5, 0})).st.x, 0.0f, 1e-5f);  // the texture's +z pole
    EXPECT_NEAR(m.map(at({10, 5, 0})).st.x, 1.0f, 1e-5f);
    EXPECT_NEAR(m.map(at({13, 0, 0})).st.x, 0.5f, 1e-5f);
}

// The derivatives of (s, t) along the footprint are those of the coordinates themselves: against
// central differences over 1e-3 of the footprint, at 2000 random points away from the poles and
// the seam.
TEST(TextureMapping, FootprintDerivativesMatchFiniteDifferences) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (TextureMappingKind kind :
         {TextureMappingKind::Spherical, TextureMappingKind::Cylindrical, TextureMappingKind::Planar}) {
        TextureMapping m = mappingOf(kind);
        m.v1 = {0.3f, -0.2f, 0.9f};
        m.v2 = {0.5f, 0.5f, 0.0f};
        int checked = 0;
        for (int i = 0; i < 2000; ++i) {
            const Vec3f p{u(rng), u(rng), u(rng)};
            const float rxy = std::hypot(p.x, p.y);
            if (rxy < 0.2f || (p.x < 0.0f && std::abs(p.y) < 0.1f))
                continue;  // the axis; the cylinder's seam
            if (kind == TextureMappingKind::Spherical && p.x > 0.0f && std::abs(p.y) < 0.1f)
                continue;  // its seam
            const Vec3f dpdx = Vec3f{u(rng), u(rng), u(rng)} * 0.01f,
                        dpdy = Vec3f{u(rng), u(rng), u(rng)} * 0.01f;
            const TextureCoordinates c = m.map(at(p, dpdx, dpdy));
            const float h = 1e-3f;
            auto difference = [&](Vec3f d) {
                const Vec2f plus = m.map(at(p + d * h)).st, minus = m.map(at(p - d * h)).st;
                return Vec2f{(plus.x - minus.x) / (2 * h), (plus.y - minus.y) / (2 * h)};
            };
            const Vec2f dx = difference(dpdx), dy = difference(dpdy);
            EXPECT_NEAR(c.dsdx, dx.x, 2e-4f);
            EXPECT_NEAR(c.dtdx, dx.y, 2e-4f);
            EXPECT_NEAR(c.dsdy, dy.x, 2e-4f);
            EXPECT_NEAR(c.dtdy, dy.y, 2e-4f);
            ++checked;
        }
        EXPECT_GT(checked, 1000);
    }
}

// The (u, v) mapping is the query's (u, v) and derivatives, then scaled and offset; a mapped
// texture is spatial (it needs the point), a (u, v) one is not.
TEST(TextureMapping, UvIsTheSurfacesCoordinatesScaledAndOffset) {
    TextureQuery query;
    query.uv = {0.25f, 0.75f};
    query.dudx = 0.1f;
    query.dvdy = 0.2f;
    Texture texture = Texture::checkerboard(Rgb(0.0f), Rgb(1.0f));
    texture.mapUv({4.0f, 2.0f}, {0.5f, 0.0f});
    const TextureCoordinates c = texture.coordinates(query);
    EXPECT_FLOAT_EQ(c.st.x, 1.5f);
    EXPECT_FLOAT_EQ(c.st.y, 1.5f);
    EXPECT_FLOAT_EQ(c.dsdx, 0.4f);
    EXPECT_FLOAT_EQ(c.dtdy, 0.4f);
    EXPECT_FALSE(texture.isSpatial());
    texture.setMapping(mappingOf(TextureMappingKind::Cylindrical));
    EXPECT_TRUE(texture.isSpatial());
    // Cylinder (s, t) of (0, 1, 0.2): (0.75, 0.2), scaled and offset (3.5, 0.4): cell (3, 0), odd.
    EXPECT_EQ(texture.evaluate(at({0, 1, 0.2f})), Rgb(1.0f));
    // (0, -1, 0.2): s 0.25 -> 1 + 0.5 = 1.5, cell (1, 0), odd; (0, -1, 0.6): t 1.2, cell (1, 1), even.
    EXPECT_EQ(texture.evaluate(at({0, -1, 0.6f})), Rgb(0.0f));
}

TEST(TextureMapping, TheLoaderReadsMappingsAndNamesWhatIsWrong) {
    auto material = [](const std::string& mapping) {
        return std::string(R"({"materials": {"m": {"type": "lambert", "albedo": {"type": "checkerboard",
            "colors": [0, 1], "mapping": )") +
               mapping + "}}}}";
    };
    const Scene scene = parseScene(
        material(
            R"({"type": "planar", "v1": [0, 0, 1], "v2": [1, 0, 0], "transform": [{"translate": [0, 0, 1]}]})"),
        "s.json");
    ASSERT_TRUE(scene.materials[0].isTextured());
    EXPECT_NO_THROW(parseScene(material(R"({"type": "uv"})"), "s.json"));
    EXPECT_NO_THROW(parseScene(material(R"({"type": "spherical"})"), "s.json"));
    auto error = [&](const std::string& mapping) {
        return std::string(testing::catchInputError([&] { parseScene(material(mapping), "s.json"); }).what());
    };
    EXPECT_CONTAINS(error(R"({"type": "conical"})"),
                    "/materials/m/albedo/mapping/type: expected one of: uv, "
                    "spherical, cylindrical, planar");
    EXPECT_CONTAINS(error(R"({"type": "spherical", "v1": [1, 0, 0]})"),
                    "/materials/m/albedo/mapping/v1: only a planar mapping takes \"v1\"");
    EXPECT_CONTAINS(error(R"({"type": "uv", "transform": []})"),
                    "/materials/m/albedo/mapping/transform: the (u, v) mapping takes no \"transform\"");
    EXPECT_CONTAINS(error(R"({"type": "planar", "scale": 2})"),
                    "/materials/m/albedo/mapping/scale: unknown key");
    // A mapped texture needs the point: not an emission's or a cut-out's.
    const InputError alpha = testing::catchInputError([] {
        parseScene(
            R"({"materials": {"m": {"type": "lambert"}}, "shapes": [{"type": "sphere", "center": [0, 0, 0],
            "radius": 1, "material": "m", "alpha": {"type": "checkerboard", "colors": [0, 1],
            "mapping": {"type": "spherical"}}}]})",
            "s.json");
    });
    EXPECT_CONTAINS(alpha.what(), "an emission or an alpha takes a texture of (u, v) only");
}

}  // namespace
}  // namespace penumbra
