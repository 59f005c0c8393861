#include "textures/procedural_texture.h"

#include <algorithm>
#include <cmath>

#include "core/perlin_noise.h"

namespace penumbra {

bool insidePolkaDot(Vec2f st) {
    const float sCell = std::floor(st.x + 0.5f), tCell = std::floor(st.y + 0.5f);
    if (!(perlinNoise({sCell + 0.5f, tCell + 0.5f, 0.5f}) > 0.0f)) return false;
    constexpr float kRadius = 0.35f, kMaxShift = 0.5f - kRadius;
    const float sCenter = sCell + kMaxShift * perlinNoise({sCell + 1.5f, tCell + 2.8f, 0.5f});
    const float tCenter = tCell + kMaxShift * perlinNoise({sCell + 4.5f, tCell + 9.8f, 0.5f});
    const float ds = st.x - sCenter, dt = st.y - tCenter;
    return ds * ds + dt * dt < kRadius * kRadius;
}

Rgb marbleColor(float t) {
    // pbrt-v4's MarbleTexture colours.
    static constexpr std::array<std::array<float, 3>, 9> kColors = {{{0.58f, 0.58f, 0.6f},
                                                                     {0.58f, 0.58f, 0.6f},
                                                                     {0.58f, 0.58f, 0.6f},
                                                                     {0.5f, 0.5f, 0.5f},
                                                                     {0.6f, 0.59f, 0.58f},
                                                                     {0.58f, 0.58f, 0.6f},
                                                                     {0.58f, 0.58f, 0.6f},
                                                                     {0.2f, 0.2f, 0.33f},
                                                                     {0.58f, 0.58f, 0.6f}}};
    constexpr int kSegments = int(kColors.size()) - 3;
    const int first = std::clamp(int(std::floor(t * float(kSegments))), 0, kSegments - 1);
    const float u = t * float(kSegments) - float(first);
    // De Casteljau on the four control colours from `first`.
    Rgb c[4];
    for (int k = 0; k < 4; ++k)
        c[k] = Rgb(kColors[first + k][0], kColors[first + k][1], kColors[first + k][2]);
    for (int level = 3; level > 0; --level)
        for (int k = 0; k < level; ++k) c[k] = c[k] * (1.0f - u) + c[k + 1] * u;
    return c[0] * 1.5f;
}

Rgb ProceduralTexture::evaluate(const TextureQuery& query, Vec2f uv) const {
    const Vec3f p = isSpatial(kind) ? worldToTexture.applyPoint(query.p) : Vec3f{};
    switch (kind) {
        case ProceduralKind::Scale: {
            const float factor = inputs[1].evaluate(query).r;
            return factor == 0.0f ? Rgb(0.0f) : inputs[0].evaluate(query) * factor;
        }
        case ProceduralKind::Mix: {
            const float amount = inputs[2].evaluate(query).r;
            const Rgb a = amount != 1.0f ? inputs[0].evaluate(query) : Rgb(0.0f);
            const Rgb b = amount != 0.0f ? inputs[1].evaluate(query) : Rgb(0.0f);
            return a * (1.0f - amount) + b * amount;
        }
        case ProceduralKind::DirectionMix: {
            const float amount = std::abs(dot(query.n, direction));
            const Rgb a = amount != 0.0f ? inputs[0].evaluate(query) : Rgb(0.0f);
            const Rgb b = amount != 1.0f ? inputs[1].evaluate(query) : Rgb(0.0f);
            return a * amount + b * (1.0f - amount);
        }
        case ProceduralKind::Bilerp:
            return corners[0] * ((1.0f - uv.x) * (1.0f - uv.y)) + corners[1] * (uv.x * (1.0f - uv.y)) +
                   corners[2] * ((1.0f - uv.x) * uv.y) + corners[3] * (uv.x * uv.y);
        case ProceduralKind::Dots:
            return insidePolkaDot(uv) ? inputs[0].evaluate(query) : inputs[1].evaluate(query);
        case ProceduralKind::Checkerboard3D: {
            const double parity = std::floor(double(p.x)) + std::floor(double(p.y)) + std::floor(double(p.z));
            const bool even = std::isfinite(parity) && std::fmod(std::abs(parity), 2.0) == 0.0;
            return even ? inputs[0].evaluate(query) : inputs[1].evaluate(query);
        }
        case ProceduralKind::Fbm:
            return Rgb(fractalNoise(p, omega, octaves));
        case ProceduralKind::Wrinkled:
            return Rgb(turbulence(p, omega, octaves));
        case ProceduralKind::Windy:
            return Rgb(std::abs(fractalNoise(p * 0.1f, 0.5f, 3)) * fractalNoise(p, 0.5f, 6));
        case ProceduralKind::Marble: {
            const Vec3f q = p * scale;
            const float t = 0.5f + 0.5f * std::sin(q.y + variation * fractalNoise(q, omega, octaves));
            return marbleColor(std::isfinite(t) ? t : 0.5f);
        }
    }
    return Rgb(0.0f);
}

}  // namespace penumbra
