#include "scenes/texture_reader.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "core/error.h"
#include "scenes/shape_reader.h"
#include "scenes/type_table.h"
#include "textures/image_texture.h"
#include "textures/procedural_texture.h"

namespace penumbra {

namespace {

struct TextureContext {
    const std::filesystem::path& folder;
    float min, max;
    int depth;  // how many textures this one is an input of
};

// [u, v] or one number for both.
Vec2f readPair(const JsonValue& value) {
    if (value.json().is_number()) return Vec2f{value.number(), value.number()};
    return value.vec2();
}

// "mapping": {"type": "uv" (the default) | "spherical" | "cylindrical" | "planar", "transform" (places
// the texture's space in the world; not for "uv"), "v1", "v2" (planar: the directions of s and t
// in that space, default x and y)} (textures/texture_mapping.h); then "uv_scale" and "uv_offset".
void readUvMapping(const JsonValue& value, Texture& texture) {
    Vec2f scale{1.0f, 1.0f}, offset{0.0f, 0.0f};
    if (auto v = value.member("uv_scale")) scale = readPair(*v);
    if (auto v = value.member("uv_offset")) offset = readPair(*v);
    texture.mapUv(scale, offset);
    const auto mappingValue = value.member("mapping");
    if (!mappingValue) return;
    const JsonObject object(*mappingValue, {"type", "transform", "v1", "v2"});
    TextureMapping mapping;
    mapping.kind =
        TextureMappingKind(object.require("type").choice({"uv", "spherical", "cylindrical", "planar"}));
    if (mapping.kind == TextureMappingKind::Uv) {
        for (const char* key : {"transform", "v1", "v2"})
            if (auto v = object.get(key)) v->fail("the (u, v) mapping takes no \"" + std::string(key) + "\"");
        return;
    }
    if (auto v = object.get("transform")) mapping.worldToTexture = readTransform(*v).inverse();
    for (const auto& [key, axis] : {std::pair{"v1", &mapping.v1}, std::pair{"v2", &mapping.v2}}) {
        if (auto v = object.get(key)) {
            if (mapping.kind != TextureMappingKind::Planar)
                v->fail("only a planar mapping takes \"" + std::string(key) + "\"");
            *axis = v->vec3();
            if (!isFinite(*axis)) v->failExpected("a finite direction");
        }
    }
    texture.setMapping(mapping);
}

Texture readConstant(const JsonValue& value, const TextureContext& context) {
    return Texture::constant(value.requiredMember("value").rgb(context.min, context.max));
}

Texture readCheckerboard(const JsonValue& value, const TextureContext& context) {
    const JsonValue colors = value.requiredMember("colors");
    if (colors.arraySize() != 2) colors.failExpected("an array of 2 colours");
    Texture texture = Texture::checkerboard(colors.element(0).rgb(context.min, context.max),
                                            colors.element(1).rgb(context.min, context.max));
    readUvMapping(value, texture);
    return texture;
}

TextureWrap readWrap(const JsonValue& value) {
    return TextureWrap(value.choice({"repeat", "clamp", "black", "mirror"}));
}

Texture readImage(const JsonValue& value, const TextureContext& context) {
    const JsonValue fileValue = value.requiredMember("file");
    const std::filesystem::path path = fileValue.existingFile(context.folder, "image");
    ImageTextureSource source;
    if (auto v = value.member("wrap")) {
        if (v->json().is_array()) {
            if (v->arraySize() != 2) v->failExpected("a wrap mode or an array of 2 (along s, along t)");
            source.wrapS = readWrap(v->element(0));
            source.wrapT = readWrap(v->element(1));
        } else {
            source.wrapS = source.wrapT = readWrap(*v);
        }
    }
    if (auto v = value.member("filter"))
        source.filter = TextureFilter(v->choice({"closest", "bilinear", "trilinear", "anisotropic"}));
    int colorSpace = PENUMBRA_COLOR_AUTO;
    if (auto v = value.member("color_space")) colorSpace = int(v->choice({"auto", "srgb", "linear"}));
    Rgb scale(1.0f);
    if (auto v = value.member("scale")) scale = v->rgb(0.0f);
    bool invert = false;
    if (auto v = value.member("invert")) invert = v->boolean();

    SourceLocation where;
    where.file = fileValue.file();
    where.jsonPointer = fileValue.pointer();
    const ImageTextureSource opened = openImageTexture(path, colorSpace, where);
    source.plugin = opened.plugin;
    source.handle = opened.handle;
    source.channels = opened.channels;
    Texture texture = Texture::image(source, scale, invert);
    readUvMapping(value, texture);
    return texture;
}

// Textures of textures nest at most this deep (a deeper file would recurse without bound).
constexpr int kMaxTextureDepth = 16;

Texture readTextureAt(const JsonValue& value, const TextureContext& context);

// An input of a composite texture: a texture object, or a colour (a number for all three
// channels) within the context's range.
Texture readInput(const JsonValue& value, const TextureContext& context) {
    if (isTextureValue(value)) {
        TextureContext inner = context;
        if (++inner.depth > kMaxTextureDepth)
            value.fail(fmt::format("textures nest at most {} deep (docs/limits.md)", kMaxTextureDepth));
        return readTextureAt(value, inner);
    }
    return Texture::constant(value.rgb(context.min, context.max));
}

// An input that scales or weighs (a scale's factor, a mix's amount): any number >= 0, or a texture.
Texture readWeight(const JsonValue& value, const TextureContext& context, float max) {
    return readInput(value, TextureContext{context.folder, 0.0f, max, context.depth});
}

// The two inputs of `key` ([a, b]).
std::array<Texture, 2> readInputPair(const JsonValue& value, const char* key, const TextureContext& context) {
    const JsonValue pair = value.requiredMember(key);
    if (pair.arraySize() != 2) pair.failExpected("an array of 2 colours or textures");
    return {readInput(pair.element(0), context), readInput(pair.element(1), context)};
}

// The space of a 3D texture: "transform" places it in the world (default: world space itself).
Transform readWorldToTexture(const JsonValue& value) {
    if (auto v = value.member("transform")) return readTransform(*v).inverse();
    return {};
}

// "octaves" (1 to 32, default 8) and "roughness" (each octave's weight relative to the last, 0 to
// 1, default 0.5: pbrt-v4's names).
void readOctaves(const JsonValue& value, ProceduralTexture& texture) {
    if (auto v = value.member("octaves")) texture.octaves = int(v->integer(1, 32));
    if (auto v = value.member("roughness")) texture.omega = v->numberInRange(0.0f, 1.0f);
}

Texture proceduralTexture(ProceduralTexture texture) {
    return Texture::procedural(std::make_shared<const ProceduralTexture>(std::move(texture)));
}

Texture readScale(const JsonValue& value, const TextureContext& context) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::Scale;
    texture.inputs = {
        readInput(value.requiredMember("texture"),
                  {context.folder, context.min, std::numeric_limits<float>::max(), context.depth}),
        readWeight(value.requiredMember("scale"), context, std::numeric_limits<float>::max())};
    return proceduralTexture(std::move(texture));
}

Texture readMix(const JsonValue& value, const TextureContext& context) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::Mix;
    const auto [a, b] = readInputPair(value, "textures", context);
    Texture amount = Texture::constant(Rgb(0.5f));
    if (auto v = value.member("amount")) amount = readWeight(*v, context, 1.0f);
    texture.inputs = {a, b, amount};
    return proceduralTexture(std::move(texture));
}

Texture readDirectionMix(const JsonValue& value, const TextureContext& context) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::DirectionMix;
    const auto [a, b] = readInputPair(value, "textures", context);
    texture.inputs = {a, b};
    if (auto v = value.member("direction")) {
        const Vec3f direction = v->vec3();
        if (!(length(direction) > 0.0f) || !std::isfinite(length(direction)))
            v->failExpected("a non-zero direction");
        texture.direction = normalize(direction);
    }
    return proceduralTexture(std::move(texture));
}

Texture readBilerp(const JsonValue& value, const TextureContext& context) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::Bilerp;
    const JsonValue values = value.requiredMember("values");
    if (values.arraySize() != 4)
        values.failExpected("an array of 4 colours: at (u, v) = (0, 0), (1, 0), (0, 1), (1, 1)");
    for (size_t k = 0; k < 4; ++k) texture.corners[k] = values.element(k).rgb(context.min, context.max);
    Texture result = proceduralTexture(std::move(texture));
    readUvMapping(value, result);
    return result;
}

Texture readDots(const JsonValue& value, const TextureContext& context) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::Dots;
    texture.inputs = {readInput(value.requiredMember("inside"), context),
                      readInput(value.requiredMember("outside"), context)};
    Texture result = proceduralTexture(std::move(texture));
    readUvMapping(value, result);
    return result;
}

Texture readCheckerboard3D(const JsonValue& value, const TextureContext& context) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::Checkerboard3D;
    const auto [a, b] = readInputPair(value, "colors", context);
    texture.inputs = {a, b};
    texture.worldToTexture = readWorldToTexture(value);
    return proceduralTexture(std::move(texture));
}

// fbm, wrinkled and windy: noise, clamped to the context's range when used.
Texture readNoise(const JsonValue& value, ProceduralKind kind) {
    ProceduralTexture texture;
    texture.kind = kind;
    if (kind != ProceduralKind::Windy) readOctaves(value, texture);
    texture.worldToTexture = readWorldToTexture(value);
    return proceduralTexture(std::move(texture));
}
Texture readFbm(const JsonValue& value, const TextureContext&) {
    return readNoise(value, ProceduralKind::Fbm);
}
Texture readWrinkled(const JsonValue& value, const TextureContext&) {
    return readNoise(value, ProceduralKind::Wrinkled);
}
Texture readWindy(const JsonValue& value, const TextureContext&) {
    return readNoise(value, ProceduralKind::Windy);
}

Texture readMarble(const JsonValue& value, const TextureContext&) {
    ProceduralTexture texture;
    texture.kind = ProceduralKind::Marble;
    readOctaves(value, texture);
    if (auto v = value.member("scale")) texture.scale = v->numberInRange(0.0f, 1e6f);
    if (auto v = value.member("variation")) texture.variation = v->numberInRange(0.0f, 1e6f);
    texture.worldToTexture = readWorldToTexture(value);
    return proceduralTexture(std::move(texture));
}

using TextureReaderFunction = Texture (*)(const JsonValue&, const TextureContext&);

const std::array<TypeRow<TextureReaderFunction>, 13> kTextureTypes{{
    {"image",
     {"type", "file", "wrap", "filter", "color_space", "scale", "invert", "uv_scale", "uv_offset", "mapping"},
     readImage},
    {"checkerboard", {"type", "colors", "uv_scale", "uv_offset", "mapping"}, readCheckerboard},
    {"constant", {"type", "value"}, readConstant},
    {"scale", {"type", "texture", "scale"}, readScale},
    {"mix", {"type", "textures", "amount"}, readMix},
    {"direction_mix", {"type", "textures", "direction"}, readDirectionMix},
    {"bilerp", {"type", "values", "uv_scale", "uv_offset", "mapping"}, readBilerp},
    {"dots", {"type", "inside", "outside", "uv_scale", "uv_offset", "mapping"}, readDots},
    {"checkerboard_3d", {"type", "colors", "transform"}, readCheckerboard3D},
    {"fbm", {"type", "octaves", "roughness", "transform"}, readFbm},
    {"wrinkled", {"type", "octaves", "roughness", "transform"}, readWrinkled},
    {"windy", {"type", "transform"}, readWindy},
    {"marble", {"type", "octaves", "roughness", "scale", "variation", "transform"}, readMarble},
}};

Texture readTextureAt(const JsonValue& value, const TextureContext& context) {
    return findTypeRow<TextureReaderFunction>(value, kTextureTypes).read(value, context);
}

}  // namespace

Texture readTexture(const JsonValue& value, const std::filesystem::path& folder, float min, float max) {
    return readTextureAt(value, TextureContext{folder, min, max, 0});
}

}  // namespace penumbra
