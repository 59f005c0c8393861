#include "textures/texture.h"

namespace penumbra {

Rgb Texture::lookupImage(Vec2f uv, const TextureQuery& query) const {
    // t = 1 - v: derivatives change sign.
    const float dsdx = query.dudx * uvScale_.x, dsdy = query.dudy * uvScale_.x;
    const float dtdx = -query.dvdx * uvScale_.y, dtdy = -query.dvdy * uvScale_.y;
    float texel[3] = {0.0f, 0.0f, 0.0f};
    const int channels = image_.channels >= 3 ? 3 : 1;
    image_.plugin->lookup(image_.handle, int(image_.wrapS), int(image_.wrapT), int(image_.filter), uv.x,
                          1.0f - uv.y, dsdx, dtdx, dsdy, dtdy, channels, texel);
    if (channels == 1) texel[1] = texel[2] = texel[0];
    return Rgb(texel[0], texel[1], texel[2]) * a_;
}

}  // namespace penumbra
