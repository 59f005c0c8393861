#include "textures/texture.h"

#include <algorithm>

#include "textures/procedural_texture.h"

namespace penumbra {

namespace {

// The first `channels` channels of `image` at `uv` (before the scale), into `texel`.
void lookupChannels(const ImageTextureSource& image, Vec2f uv, Vec2f uvScale, const TextureQuery& query,
                    int channels, float* texel) {
    // t = 1 - v: derivatives change sign.
    const float dsdx = query.dudx * uvScale.x, dsdy = query.dudy * uvScale.x;
    const float dtdx = -query.dvdx * uvScale.y, dtdy = -query.dvdy * uvScale.y;
    image.plugin->lookup(image.handle, int(image.wrapS), int(image.wrapT), int(image.filter), uv.x,
                         1.0f - uv.y, dsdx, dtdx, dsdy, dtdy, channels, texel);
}

}  // namespace

Rgb Texture::lookupImage(Vec2f uv, const TextureQuery& query) const {
    float texel[3] = {0.0f, 0.0f, 0.0f};
    const int channels = image_.channels >= 3 ? 3 : 1;
    lookupChannels(image_, uv, uvScale_, query, channels, texel);
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
    const Vec2f uv{query.uv.x * uvScale_.x + uvOffset_.x, query.uv.y * uvScale_.y + uvOffset_.y};
    float texel[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    lookupChannels(image_, uv, uvScale_, query, image_.channels, texel);
    const float alpha = texel[image_.channels - 1] * a_.r;
    return invert_ ? std::max(0.0f, 1.0f - alpha) : alpha;
}

}  // namespace penumbra
