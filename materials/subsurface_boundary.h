// The surface of a subsurface material (pbrt-v4's `subsurface`; the interior is a homogeneous
// medium that the volumetric integrator walks: scenes/material_interior.h). Light arriving from
// outside meets a dielectric interface, smooth or rough (`Surface`: Dielectric or
// RoughDielectric): it is reflected, or refracted into the medium. Light that the walk brings back
// to the surface from inside is reflected back in with the smooth interface's Fresnel reflectance
// for its direction (total internal reflection included), specularly, as the exact interface
// would; the rest leaves diffusely: a cosine-distributed direction outside, times eta^2 (radiance
// regains the factor 1 / eta^2 its refraction in took), as pbrt-v4's BSSRDF leaves through its Sw
// lobe and Cycles' random walk through a diffuse closure at its exit point. The diffuse exit is
// what lets light be sampled where the walk comes out (through a smooth interface no light point
// could be aimed at); only the exit's direction differs from the exact interface's (refracted),
// so what a slab reflects of a uniform sky is the exact interface's (docs/subsurface.md).
// Energy is conserved: a non-absorbing interior under a uniform sky stays white
// (tests/renderer/subsurface_render_test.cpp). Not reciprocal: light and importance cross the
// surface differently.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/dielectric.h"
#include "materials/fresnel.h"
#include "materials/rough_dielectric.h"
#include "materials/subsurface_albedo.h"

namespace penumbra {

// Interior coefficients that vary over the surface: textures of sigma_a and sigma_s, or of the
// reflectance and its mean free path, written at each shading point (Material::at) and taken by
// the walk that enters there instead of its medium's, as pbrt-v4 evaluates its BSSRDF's
// coefficients where light enters. The walk keeps them until it leaves.
struct TexturedInterior {
    enum class Kind : uint8_t { None, Coefficients, Reflectance };
    Kind kind = Kind::None;
    Rgb sigmaA{0.0f}, sigmaS{0.0f};             // Coefficients: per unit length, before scale
    Rgb reflectance{0.0f}, meanFreePath{1.0f};  // Reflectance
    float scale = 1.0f;
    float g = 0.0f;                    // the medium's asymmetry (the reflectance's inversion keeps it)
    float internalReflectance = 0.0f;  // diffuseFresnelReflectance(1 / eta), for the inversion

    // sigma_a and sigma_s here; none when nothing is textured (the medium's own hold) or the
    // values give no finite medium.
    std::optional<std::pair<Rgb, Rgb>> coefficients() const {
        if (kind == Kind::None) return std::nullopt;
        Rgb a = sigmaA * scale, s = sigmaS * scale;
        if (kind == Kind::Reflectance)
            for (int c = 0; c < 3; ++c) {
                const double length = double(meanFreePath[c]) * scale;
                if (!(length > 0.0)) return std::nullopt;
                const SubsurfaceCoefficients k =
                    coefficientsForDiffuseReflectance(reflectance[c], length, internalReflectance, g);
                (c == 0 ? a.r : c == 1 ? a.g : a.b) = float(k.sigmaA);
                (c == 0 ? s.r : c == 1 ? s.g : s.b) = float(k.sigmaS);
            }
        if (!(a + s).isFinite()) return std::nullopt;
        return std::pair{a, s};
    }
};

template <class Surface>
struct SubsurfaceBoundary {
    Surface surface;  // what light from outside meets; its eta: interior index over exterior
    TexturedInterior interior{};

    static constexpr BsdfFlags kFlags = Surface::kFlags | BsdfFlags::Diffuse | BsdfFlags::Transmission |
                                        BsdfFlags::Specular | BsdfFlags::Reflection;

    // The share of light from inside, arriving along -wo, that the interface reflects back in.
    float internalReflectance(Vec3f wo) const {
        return fresnelDielectric(std::abs(wo.z), 1.0f / surface.eta);
    }

    // `front`: whether wo lies outside (on the geometric surface's front, local +z).
    Rgb eval(Vec3f wo, Vec3f wi, bool front) const {
        if (front) return surface.eval(wo, wi, true);
        if (!(wi.z > 0.0f)) return Rgb(0.0f);
        return Rgb((1.0f - internalReflectance(wo)) * surface.eta * surface.eta * kInvPi);
    }
    float pdf(Vec3f wo, Vec3f wi, bool front) const {
        if (front) return surface.pdf(wo, wi, true);
        return wi.z > 0.0f ? (1.0f - internalReflectance(wo)) * cosineHemispherePdf(wi.z) : 0.0f;
    }
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool front) const {
        if (front) return surface.sample(wo, uLobe, u, true);
        const float reflect = internalReflectance(wo);
        if (uLobe < reflect) return BsdfSample{reflectAboutZ(wo), Rgb(1.0f), reflect, kSpecularReflection};
        const Vec3f wi = sampleCosineHemisphere(u);
        const float pdfValue = (1.0f - reflect) * cosineHemispherePdf(wi.z);
        if (!(pdfValue > 0.0f)) return std::nullopt;
        return BsdfSample{wi, Rgb(surface.eta * surface.eta), pdfValue,
                          BsdfFlags::Diffuse | BsdfFlags::Transmission, 1.0f / surface.eta};
    }
    Rgb reflectanceForAov() const { return Rgb(1.0f); }
};

}  // namespace penumbra
