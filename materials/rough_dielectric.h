// A rough dielectric interface (frosted glass): reflection and refraction through a microsurface,
// after Walter, Marschner, Li and Torrance 2007, "Microfacet models for refraction through rough
// surfaces", with Smith's height-correlated G (as pbrt-v4's DielectricBxDF). With eta the relative index of
// the far side over wo's side:
//
//   reflection (wi on wo's side),   wm = normalize(wo + wi):
//     f = D(wm) G(wo, wi) F(wo.wm) / (4 |wo.z| |wi.z|)
//   refraction (wi on the far side), wm = normalize(wo + eta wi) (turned to wo's side):
//     f = D(wm) G(wo, wi) (1 - F(wo.wm)) |wi.wm| |wo.wm| / ((wi.wm + wo.wm / eta)^2 |wi.z| |wo.z|) / eta^2
//
// The 1 / eta^2 is the radiance scale of the smooth Dielectric (dielectric.h), and as there the
// sample reports eta so that Russian roulette can leave it out. Microfacets that face away from
// either direction contribute nothing. Sampling draws a microfacet normal (microfacet.h), then
// reflects with probability F(wo.wm) and refracts otherwise. Which side is the inside is decided by `front`
// (the geometric side of wo), as for Dielectric; Beer-Lambert absorption in the interior likewise.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/dielectric.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"

namespace penumbra {

struct RoughDielectric {
    float eta = 1.5f;  // interior index over exterior index, > 0
    FresnelModel fresnel = FresnelModel::Exact;
    Rgb absorption{0.0f, 0.0f, 0.0f};  // sigma_a of the interior, per unit length (0: clear)
    MicrofacetDistribution distribution;

    static constexpr BsdfFlags kFlags = BsdfFlags::Glossy | BsdfFlags::Reflection | BsdfFlags::Transmission;

    // Reflectance of a microfacet seen at cos(theta) = cosine > 0 from the side of relative index eta.
    float reflectance(float cosine, float etaRelative) const {
        return fresnel == FresnelModel::Schlick ? fresnelSchlick(cosine, etaRelative)
                                                : fresnelDielectric(cosine, etaRelative);
    }

    Rgb eval(Vec3f wo, Vec3f wi, bool front) const {
        const Geometry g = geometryOf(wo, wi, front);
        if (!g.valid) return Rgb(0.0f);
        const float F = reflectance(g.cosO, g.eta);
        if (g.reflects) return Rgb(F * distribution.reflectionWithoutFresnel(g.wo, g.wi, g.wm));
        const float denominator = sqr(g.cosI + g.cosO / g.eta) * g.wi.z * g.wo.z;
        return Rgb(distribution.D(g.wm) * distribution.G(g.wo, g.wi) * (1.0f - F) *
                   std::abs(g.cosI * g.cosO / denominator) / (g.eta * g.eta));
    }

    float pdf(Vec3f wo, Vec3f wi, bool front) const {
        const Geometry g = geometryOf(wo, wi, front);
        if (!g.valid) return 0.0f;
        const float F = reflectance(g.cosO, g.eta);
        return lobeDensity(g) * (g.reflects ? F : 1.0f - F);
    }

    // One lobe alone, for the walk between a layered material's interfaces (layered_bsdf.h): a
    // microfacet normal sampled as sample() does, then always reflected or always refracted; its
    // density is lobePdf, pdf() without the choice between the lobes.
    std::optional<BsdfSample> sampleLobe(Vec3f wo, Vec2f u, bool transmission, bool front) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        const Vec3f woUp{wo.x, wo.y, wo.z * side};
        const float etaRelative = front ? eta : 1.0f / eta;
        const Vec3f wm = distribution.sampleNormal(woUp, u);
        if (!(dot(woUp, wm) > 0.0f)) return std::nullopt;
        Vec3f wi;
        if (transmission) {
            const std::optional<Vec3f> refracted = refractAbout(woUp, wm, etaRelative);
            if (!refracted || !(refracted->z < 0.0f)) return std::nullopt;
            wi = *refracted;
        } else {
            wi = reflectAbout(woUp, wm);
            if (!(wi.z > 0.0f)) return std::nullopt;
        }
        wi.z *= side;
        const float pdfValue = lobePdf(wo, wi, front);
        if (!(pdfValue > 0.0f)) return std::nullopt;
        const BsdfFlags lobe = transmission ? BsdfFlags::Transmission : BsdfFlags::Reflection;
        return BsdfSample{wi, eval(wo, wi, front) * (std::abs(wi.z) / pdfValue), pdfValue,
                          BsdfFlags::Glossy | lobe, transmission ? etaRelative : 1.0f};
    }
    float lobePdf(Vec3f wo, Vec3f wi, bool front) const {
        const Geometry g = geometryOf(wo, wi, front);
        return g.valid ? lobeDensity(g) : 0.0f;
    }

    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool front) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        const Vec3f woUp{wo.x, wo.y, wo.z * side};
        const float etaRelative = front ? eta : 1.0f / eta;
        const Vec3f wm = distribution.sampleNormal(woUp, u);
        if (!(dot(woUp, wm) > 0.0f)) return std::nullopt;  // a microfacet facing away (Beckmann's sampling)
        const float F = reflectance(dot(woUp, wm), etaRelative);
        Vec3f wi;
        BsdfFlags flags;
        if (uLobe < F) {
            wi = reflectAbout(woUp, wm);
            if (!(wi.z > 0.0f)) return std::nullopt;
            flags = BsdfFlags::Glossy | BsdfFlags::Reflection;
        } else {
            const std::optional<Vec3f> refracted = refractAbout(woUp, wm, etaRelative);
            if (!refracted || !(refracted->z < 0.0f)) return std::nullopt;
            wi = *refracted;
            flags = BsdfFlags::Glossy | BsdfFlags::Transmission;
        }
        wi.z *= side;
        const float pdfValue = pdf(wo, wi, front);
        if (!(pdfValue > 0.0f)) return std::nullopt;
        const bool transmits = any(flags & BsdfFlags::Transmission);
        return BsdfSample{wi, eval(wo, wi, front) * (std::abs(wi.z) / pdfValue), pdfValue, flags,
                          transmits ? etaRelative : 1.0f};
    }

    Rgb reflectanceForAov() const { return Rgb(1.0f); }
    // The medium behind the surface (Material::interiorAbsorption).
    Rgb interiorAbsorption() const { return absorption; }

private:
    static float sqr(float x) { return x * x; }

    // A direction pair turned so that wo is on the +z side, with the microfacet normal that
    // connects them; not valid when the pair has no such normal or it faces away from either.
    struct Geometry {
        bool valid = false, reflects = false;
        Vec3f wo, wi, wm;
        float cosO = 0, cosI = 0;  // wo.wm and wi.wm
        float eta = 1;             // of the far side over wo's (the interface's, whichever side wi is on)
    };
    Geometry geometryOf(Vec3f wo, Vec3f wi, bool front) const {
        Geometry g;
        if (wo.z == 0.0f || wi.z == 0.0f) return g;
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        g.wo = {wo.x, wo.y, wo.z * side};
        g.wi = {wi.x, wi.y, wi.z * side};
        g.reflects = g.wi.z > 0.0f;
        g.eta = front ? eta : 1.0f / eta;
        const Vec3f half = g.reflects ? g.wi + g.wo : g.wi * g.eta + g.wo;  // the generalized half vector
        if (lengthSquared(half) == 0.0f) return g;
        g.wm = normalize(half);
        if (g.wm.z < 0.0f) g.wm = -g.wm;
        g.cosO = dot(g.wo, g.wm);
        g.cosI = dot(g.wi, g.wm);
        // Each direction must see the microfacet from its own side of the macro surface.
        if (!(g.cosO > 0.0f) || !(g.cosI * g.wi.z > 0.0f)) return g;
        g.valid = true;
        return g;
    }

    // The density of wi within its lobe: the microfacet normal's, times the Jacobian dwm / dwi of
    // reflection or of refraction.
    float lobeDensity(const Geometry& g) const {
        if (g.reflects) return distribution.reflectionPdf(g.wo, g.wm);
        return distribution.normalPdf(g.wo, g.wm) * std::abs(g.cosI) / sqr(g.cosI + g.cosO / g.eta);
    }
};

}  // namespace penumbra
