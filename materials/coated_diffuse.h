// A diffuse base under a clear dielectric coating (plastic, varnished wood, paint): Mitsuba's
// `plastic` / `roughplastic` model (Jakob; after Weidlich and Wilkie 2007, "Arbitrarily layered
// micro-facet surfaces"). Two lobes:
//   - the coating's reflection: a mirror lobe (CoatedDiffuse) or a microfacet lobe as RoughDielectric's
//     reflection (RoughCoatedDiffuse), with the coating's Fresnel reflectance F;
//   - the base seen through the coating: light enters (1 - F(wi)), reaches the Lambertian base of
//     albedo rho, bounces between base and coating (the coating reflects back the fraction
//     F_int of diffuse light from inside), and leaves (1 - F(wo)), its radiance scaled by 1 / eta^2:
//         f_base = rho (1 - F(wi.z)) (1 - F(wo.z)) / (pi eta^2 (1 - rho F_int)).
// The approximation: the base term uses the smooth coating's Fresnel at the macro normal even
// under a rough coating (Mitsuba's roughplastic uses precomputed rough transmittances instead),
// and the base's light is diffuse when it meets the coating from inside. Energy: with a smooth
// coating the albedo is F(wo) + (1 - F(wo)) rho (1 - F_int) / (1 - rho F_int), exactly 1 for
// rho = 1 (a white furnace test checks it); a rough coating loses the microfacets' multiple
// scattering (tests/materials/microfacet_test.cpp measures it). Two-sided: evaluated on wo's side.
#pragma once

#include <cmath>
#include <optional>

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"

namespace penumbra {

template <bool kRough>
struct CoatedDiffuseModel {
    Rgb albedo{0.5f, 0.5f, 0.5f};         // the base's, each channel in [0, 1]
    float eta = 1.5f;                     // the coating's index over the outside's, > 0
    MicrofacetDistribution distribution;  // the coating's roughness (RoughCoatedDiffuse only)
    // diffuseFresnelReflectance(1 / eta): the diffuse light the coating reflects back inside.
    float internalReflectance = float(diffuseFresnelReflectance(1.0 / 1.5));

    static constexpr BsdfFlags kFlags =
        BsdfFlags::Diffuse | BsdfFlags::Reflection | (kRough ? BsdfFlags::Glossy : BsdfFlags::Specular);

    static CoatedDiffuseModel make(Rgb albedo, float eta, MicrofacetDistribution distribution = {}) {
        return {albedo, eta, distribution, float(diffuseFresnelReflectance(1.0 / eta))};
    }

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        if (!(wo.z * wi.z > 0.0f)) return Rgb(0.0f);
        const float cosO = std::abs(wo.z), cosI = std::abs(wi.z);
        const float transmit = (1.0f - fresnelDielectric(cosI, eta)) * (1.0f - fresnelDielectric(cosO, eta));
        Rgb f = base() * (transmit * kInvPi / (eta * eta));
        if constexpr (kRough) f += Rgb(coatingReflection(wo, wi));
        return f;
    }

    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        if (!(wo.z * wi.z > 0.0f)) return 0.0f;
        const float pCoat = coatingProbability(wo);
        float density = (1.0f - pCoat) * cosineHemispherePdf(std::abs(wi.z));
        if constexpr (kRough) density += pCoat * coatingPdf(wo, wi);
        return density;
    }

    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool front) const {
        if (wo.z == 0.0f) return std::nullopt;
        const float pCoat = coatingProbability(wo);
        Vec3f wi;
        if (uLobe < pCoat) {
            if constexpr (!kRough) {
                const float F = fresnelDielectric(std::abs(wo.z), eta);
                return BsdfSample{reflectAboutZ(wo), Rgb(F / pCoat), pCoat,
                                  BsdfFlags::Specular | BsdfFlags::Reflection};
            } else {
                const float side = wo.z > 0.0f ? 1.0f : -1.0f;
                const Vec3f woUp{wo.x, wo.y, wo.z * side};
                const Vec3f wm = distribution.sampleNormal(woUp, u);
                if (!(dot(woUp, wm) > 0.0f))
                    return std::nullopt;  // a microfacet facing away (Beckmann's sampling)
                wi = reflectAbout(woUp, wm);
                if (!(wi.z > 0.0f)) return std::nullopt;
                wi.z *= side;
            }
        } else {
            wi = sampleCosineHemisphere(u);
            if (wo.z < 0.0f) wi.z = -wi.z;
        }
        const float pdfValue = pdf(wo, wi, front);
        if (!(pdfValue > 0.0f)) return std::nullopt;
        const BsdfFlags lobe = uLobe < pCoat ? BsdfFlags::Glossy : BsdfFlags::Diffuse;
        return BsdfSample{wi, eval(wo, wi, front) * (std::abs(wi.z) / pdfValue), pdfValue,
                          lobe | BsdfFlags::Reflection};
    }

    Rgb reflectanceForAov() const { return albedo; }

    // The base's albedo as seen through the coating, inter-reflections included: rho / (1 - rho F_int).
    Rgb base() const {
        return {albedo.r / (1.0f - albedo.r * internalReflectance),
                albedo.g / (1.0f - albedo.g * internalReflectance),
                albedo.b / (1.0f - albedo.b * internalReflectance)};
    }

    // Probability of sampling the coating's lobe: its Fresnel reflectance against the base's
    // luminance, as Mitsuba's plastic (1 when the base is black).
    float coatingProbability(Vec3f wo) const {
        const float F = fresnelDielectric(std::abs(wo.z), eta);
        const float coatWeight = 1.0f / (1.0f + albedo.luminance());
        const float coat = F * coatWeight, diffuse = (1.0f - F) * (1.0f - coatWeight);
        return coat + diffuse > 0.0f ? coat / (coat + diffuse) : 1.0f;
    }

private:
    // The rough coating's reflection lobe (as RoughDielectric's) and its sampling density.
    float coatingReflection(Vec3f wo, Vec3f wi) const {
        const auto pair = reflectionPair(wo, wi);
        if (!pair) return 0.0f;
        return fresnelDielectric(dot(pair->wo, pair->wm), eta) *
               distribution.reflectionWithoutFresnel(pair->wo, pair->wi, pair->wm);
    }
    float coatingPdf(Vec3f wo, Vec3f wi) const {
        const auto pair = reflectionPair(wo, wi);
        return pair ? distribution.reflectionPdf(pair->wo, pair->wm) : 0.0f;
    }
};

using CoatedDiffuse = CoatedDiffuseModel<false>;
using RoughCoatedDiffuse = CoatedDiffuseModel<true>;

}  // namespace penumbra
