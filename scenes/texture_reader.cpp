#include "scenes/texture_reader.h"

#include <fmt/format.h>

#include <array>

#include "core/error.h"
#include "scenes/type_table.h"
#include "textures/image_texture.h"

namespace penumbra {

namespace {

struct TextureContext {
    const std::filesystem::path& folder;
    float min, max;
};

// [u, v] or one number for both.
Vec2f readPair(const JsonValue& value) {
    if (value.json().is_number()) return Vec2f{value.number(), value.number()};
    return value.vec2();
}

void readUvMapping(const JsonValue& value, Texture& texture) {
    Vec2f scale{1.0f, 1.0f}, offset{0.0f, 0.0f};
    if (auto v = value.member("uv_scale")) scale = readPair(*v);
    if (auto v = value.member("uv_offset")) offset = readPair(*v);
    texture.mapUv(scale, offset);
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

    SourceLocation where;
    where.file = fileValue.file();
    where.jsonPointer = fileValue.pointer();
    const ImageTextureSource opened = openImageTexture(path, colorSpace, where);
    source.plugin = opened.plugin;
    source.handle = opened.handle;
    source.channels = opened.channels;
    Texture texture = Texture::image(source, scale);
    readUvMapping(value, texture);
    return texture;
}

using TextureReaderFunction = Texture (*)(const JsonValue&, const TextureContext&);

const std::array<TypeRow<TextureReaderFunction>, 3> kTextureTypes{{
    {"image", {"type", "file", "wrap", "filter", "color_space", "scale", "uv_scale", "uv_offset"}, readImage},
    {"checkerboard", {"type", "colors", "uv_scale", "uv_offset"}, readCheckerboard},
    {"constant", {"type", "value"}, readConstant},
}};

}  // namespace

Texture readTexture(const JsonValue& value, const std::filesystem::path& folder, float min, float max) {
    const TextureContext context{folder, min, max};
    return findTypeRow<TextureReaderFunction>(value, kTextureTypes).read(value, context);
}

}  // namespace penumbra
