// The vocabulary every material speaks: the flags that say what its lobes are, and the one sample
// type that all of them return. Properties the integrator asks ("purely specular", "chooses
// between lobes") are derived from the flags, never listed by hand.
#pragma once

#include <bit>
#include <cstdint>

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

// What a lobe (or a material's set of lobes) is: its scattering type and its direction.
enum class BsdfFlags : uint8_t {
    None = 0,
    Reflection = 1 << 0,    // wi on wo's side of the shading frame
    Transmission = 1 << 1,  // wi on the other side
    Diffuse = 1 << 2,
    Glossy = 1 << 3,
    Specular = 1 << 4,  // a delta distribution: sampled, never evaluated
};

constexpr BsdfFlags operator|(BsdfFlags a, BsdfFlags b) { return BsdfFlags(uint8_t(a) | uint8_t(b)); }
constexpr BsdfFlags operator&(BsdfFlags a, BsdfFlags b) { return BsdfFlags(uint8_t(a) & uint8_t(b)); }
constexpr bool any(BsdfFlags f) { return f != BsdfFlags::None; }

constexpr BsdfFlags kScatteringTypes = BsdfFlags::Diffuse | BsdfFlags::Glossy | BsdfFlags::Specular;
constexpr BsdfFlags kDirections = BsdfFlags::Reflection | BsdfFlags::Transmission;

// Every lobe is a delta distribution: eval() and pdf() are 0 everywhere, so next-event estimation
// cannot contribute.
constexpr bool isPurelySpecular(BsdfFlags f) { return (f & kScatteringTypes) == BsdfFlags::Specular; }
// More than one lobe (two scattering types, or reflection and transmission): sample() picks one
// with its uLobe argument, which the integrator must then draw.
constexpr bool hasSeveralLobes(BsdfFlags f) {
    return std::popcount(uint8_t(f & kScatteringTypes)) > 1 || std::popcount(uint8_t(f & kDirections)) > 1;
}

struct BsdfSample {
    Vec3f wi;
    Rgb weight;     // f * |cos(theta_i)| / pdf
    float pdf = 0;  // solid-angle density of wi (for a specular lobe: the lobe's choice probability)
    BsdfFlags flags = BsdfFlags::None;  // the lobe sampled: one scattering type, one direction
    // Relative index eta(wi side) / eta(wo side) of a refraction (1 otherwise). The weight of a
    // refraction carries the radiance scale 1 / eta^2; a path's throughput times the product of
    // the eta^2 is free of it (Russian roulette uses that).
    float eta = 1.0f;

    bool isSpecular() const { return any(flags & BsdfFlags::Specular); }
    bool isTransmission() const { return any(flags & BsdfFlags::Transmission); }
};

}  // namespace penumbra
