#include "textures/texture.h"

#include <algorithm>

#include "textures/procedural_texture.h"

namespace penumbra {

namespace {

// The first `channels` channels of `image` at `c` (before the scale), into `texel`.
void lookupChannels(const ImageTextureSource& image, const TextureCoordinates& c, int channels,
                    float* texel) {
    // The image's row coordinate is 1 - t: t's derivatives change sign.
    image.plugin->lookup(image.handle, int(image.wrapS), int(image.wrapT), int(image.filter), c.st.x,
                         1.0f - c.st.y, c.dsdx, -c.dtdx, c.dsdy, -c.dtdy, channels, texel);
}

}  // namespace

Rgb Texture::lookupImage(const TextureCoordinates& c) const {
    float texel[3] = {0.0f, 0.0f, 0.0f};
    const int channels = image_.channels >= 3 ? 3 : 1;
    lookupChannels(image_, c, channels, texel);
    if (channels == 1) texel[1] = texel[2] = texel[0];
    const Rgb scaled = Rgb(texel[0], texel[1], texel[2]) * a_;
    if (!invert_) return scaled;
    return {std::max(0.0f, 1.0f - scaled.r), std::max(0.0f, 1.0f - scaled.g),
            std::max(0.0f, 1.0f - scaled.b)};
}

Texture Texture::procedural(std::shared_ptr<const ProceduralTexture> procedural) {
    Texture t;
    t.kind_ = TextureKind::Procedural;
    t.spatial_ = penumbra::isSpatial(procedural->kind);
    for (const Texture& input : procedural->inputs) {
        t.proceduralNeedsFootprint_ = t.proceduralNeedsFootprint_ || input.needsFootprint();
        t.spatial_ = t.spatial_ || input.isSpatial();
    }
    t.procedural_ = std::move(procedural);
    return t;
}

Rgb Texture::evaluateProcedural(const TextureQuery& query, Vec2f uv) const {
    return procedural_->evaluate(query, uv);
}

float Texture::lookupAlpha(const TextureQuery& query) const {
    float texel[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    lookupChannels(image_, coordinates(query), image_.channels, texel);
    const float alpha = texel[image_.channels - 1] * a_.r;
    return invert_ ? std::max(0.0f, 1.0f - alpha) : alpha;
}

}  // namespace penumbra
