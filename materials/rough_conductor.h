// A rough metal: the conductor's complex Fresnel reflectance on a microsurface (Cook-Torrance with
// Smith's height-correlated G, as pbrt-v4's ConductorBxDF and Mitsuba 3's roughconductor):
//
//     f(wo, wi) = D(wm) G(wo, wi) F(wo.wm) / (4 |wo.z| |wi.z|),   wm = normalize(wo + wi).
//
// Directions are drawn from the distribution's normals (microfacet.h). Single scattering only: light that
// would bounce between microfacets is lost, so even F = 1 reflects less than 1 at high roughness
// (tests/materials/microfacet_test.cpp measures how much). Two-sided like Conductor: evaluated on the side
// where wo lies.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"

namespace penumbra {

struct RoughConductor {
    Rgb eta{0.143f, 0.374f, 1.442f};
    Rgb k{3.983f, 2.385f, 1.603f};
    MicrofacetDistribution distribution;
    Rgb tint{1.0f, 1.0f, 1.0f};  // a factor on the reflectance (as Conductor's)

    static constexpr BsdfFlags kFlags = BsdfFlags::Glossy | BsdfFlags::Reflection;

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        const auto pair = reflectionPair(wo, wi);
        if (!pair) return Rgb(0.0f);
        return fresnelComplex(dot(pair->wo, pair->wm), eta, k) * tint *
               distribution.reflectionWithoutFresnel(pair->wo, pair->wi, pair->wm);
    }

    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        const auto pair = reflectionPair(wo, wi);
        return pair ? distribution.reflectionPdf(pair->wo, pair->wm) : 0.0f;
    }

    std::optional<BsdfSample> sample(Vec3f wo, float /*uLobe*/, Vec2f u, bool front) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        const Vec3f woUp{wo.x, wo.y, wo.z * side};
        const Vec3f wm = distribution.sampleNormal(woUp, u);
        if (!(dot(woUp, wm) > 0.0f)) return std::nullopt;  // a microfacet facing away (Beckmann's sampling)
        Vec3f wi = reflectAbout(woUp, wm);
        if (!(wi.z > 0.0f)) return std::nullopt;  // reflected below the surface: the light is lost
        wi.z *= side;
        const float pdfValue = pdf(wo, wi, front);
        if (!(pdfValue > 0.0f)) return std::nullopt;
        return BsdfSample{wi, eval(wo, wi, front) * (std::abs(wi.z) / pdfValue), pdfValue, kFlags};
    }

    // At normal incidence, as denoisers expect an albedo.
    Rgb reflectanceForAov() const { return fresnelComplex(1.0f, eta, k) * tint; }
};

}  // namespace penumbra
