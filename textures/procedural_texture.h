// pbrt-v4's procedural and composite textures: a texture of other textures (scale, mix, direction
// mix), of the surface's (u, v) (bilinear interpolation, polka dots) or of the point in a space of
// the texture's own (a 3D checkerboard, fractal noise, wrinkles, wind-swept waves, marble). Their
// definitions are pbrt-v4's (textures.h), with Perlin's noise (core/perlin_noise.h).
//
// Point-sampled: noise textures sum all their octaves whatever the pixel's footprint (pbrt-v4
// drops the octaves finer than the footprint; its expectation over a pixel is then about the same)
// and the 3D checkerboard is not box-filtered; the pixel filter anti-aliases.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/rgb.h"
#include "core/transform.h"
#include "textures/texture.h"

namespace penumbra {

enum class ProceduralKind : uint8_t {
    Scale,           // inputs[0] times inputs[1]'s first channel
    Mix,             // (1 - amount) inputs[0] + amount inputs[1], amount inputs[2]'s first channel
    DirectionMix,    // |n . direction| inputs[0] + (1 - |n . direction|) inputs[1]
    Bilerp,          // corners (v00, v10, v01, v11) interpolated over the mapped (u, v)
    Dots,            // inputs[0] inside pbrt-v4's polka dots of the mapped (u, v), inputs[1] outside
    Checkerboard3D,  // inputs[0] where floor(x) + floor(y) + floor(z) is even, inputs[1] where odd
    Fbm,             // fractalNoise(p, omega, octaves)
    Wrinkled,        // turbulence(p, omega, octaves)
    Windy,           // |fractalNoise(p / 10, 0.5, 3)| fractalNoise(p, 0.5, 6)
    Marble,          // pbrt-v4's marble colour spline over sin(y + variation fractalNoise(p))
};

// Whether a kind is looked up at the point (and the normal), not only at (u, v).
constexpr bool isSpatial(ProceduralKind kind) {
    return kind == ProceduralKind::DirectionMix || kind >= ProceduralKind::Checkerboard3D;
}

struct ProceduralTexture {
    ProceduralKind kind = ProceduralKind::Scale;
    std::vector<Texture> inputs;
    std::array<Rgb, 4> corners{};       // Bilerp
    Vec3f direction{0.0f, 1.0f, 0.0f};  // DirectionMix: unit, in world space
    Transform worldToTexture;           // the 3D kinds' space
    int octaves = 8;
    float omega = 0.5f;      // each octave's weight relative to the last (pbrt-v4's "roughness")
    float scale = 1.0f;      // Marble: of the point
    float variation = 0.2f;  // Marble: of the noise's turn of the stripes

    // The value at `query` (the point and normal in world space), `uv` being the query's (u, v)
    // through the texture's own mapping.
    Rgb evaluate(const TextureQuery& query, Vec2f uv) const;
};

// Whether (s, t) lies inside one of pbrt-v4's polka dots: a dot of radius 0.35 in the cells about
// the integer points whose noise is positive, moved within its cell by more noise.
bool insidePolkaDot(Vec2f st);

// pbrt-v4's marble colour at t in [0, 1]: a cubic Bezier spline through nine greys and one
// slate blue, times 1.5.
Rgb marbleColor(float t);

}  // namespace penumbra
