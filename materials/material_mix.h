// A mix of two materials (pbrt-v4's MixMaterial): at each shading point one of the two is used
// whole, the second with probability `amount` (a constant or a texture's first channel over the
// surface's (u, v)), chosen by a hash of the point, the direction it is seen from and the mix's
// own index, as pbrt-v4 chooses (MixMaterial::ChooseMaterial). The image is then the blend of the
// two materials' images in expectation, with no BSDF of two lobes to build; the same point seen
// along the same direction always gets the same material, whatever the backend or thread. A mix
// may name another mix; the scene loader refuses cycles and interfaces (a medium boundary is not a
// surface that could be mixed).
#pragma once

#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/hash.h"
#include "core/vec.h"
#include "textures/texture.h"

namespace penumbra {

struct MaterialMix {
    uint32_t first = 0, second = 0;  // indices into the scene's materials
    float amount = 0.5f;             // the probability of `second`, when there is no texture
    std::shared_ptr<const Texture> amountTexture;

    // Which of the two at point p (geometric normal n) seen along wo (towards the viewer), `self`
    // being the mix's own index; uv, p and n for the texture, looked up without a footprint (the
    // finest level).
    uint32_t choose(Vec3f p, Vec3f n, Vec3f wo, Vec2f uv, uint32_t self) const {
        float a = amount;
        if (amountTexture) {
            TextureQuery query;
            query.uv = uv;
            query.p = p;
            query.n = n;
            a = amountTexture->evaluate(query).r;
        }
        if (!(a > 0.0f)) return first;
        if (a >= 1.0f) return second;
        const uint64_t h = hashWords(std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y),
                                     std::bit_cast<uint32_t>(p.z), std::bit_cast<uint32_t>(wo.x),
                                     std::bit_cast<uint32_t>(wo.y), std::bit_cast<uint32_t>(wo.z), self);
        return bitsToUnitFloat(uint32_t(h >> 32)) < a ? second : first;
    }
};

}  // namespace penumbra
