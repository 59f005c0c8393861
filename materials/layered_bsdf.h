// A base under a dielectric coat, evaluated by a random walk between the two interfaces: pbrt-v4's
// LayeredBxDF (Pharr, Jakob and Humphreys 2023, "Physically Based Rendering", 4th ed., section
// 14.3; the stochastic layered evaluation of Guo, Hasan and Zhao 2018, "Position-free Monte Carlo
// simulation for arbitrary layered BSDFs"), as pbrt-v4's `coateddiffuse` and `coatedconductor`
// use it. The coat is a smooth or rough dielectric (Dielectric, RoughDielectric), the base a
// Lambertian reflector or a smooth or rough conductor whose index is taken relative to the coat's.
// Between them lies a slab of `thickness` with extinction 1 per unit length: absorbing when its
// `albedo` is black (pbrt-v4's default thickness 0.01 absorbs a few per cent at normal
// incidence), scattering with albedo and a Henyey-Greenstein phase function (g) otherwise.
//
// Nothing is tabulated. eval() is an unbiased estimate: `samples` walks of at most `maxDepth`
// scattering events, each entering through the coat from wo, reflecting between the interfaces
// (and scattering in the slab), and connecting to wi at every vertex through the coat's
// transmission from wi (a next-event estimate, combined with the walk's own directions by the power
// heuristic). pdf() is an estimate of the density too, mixed with the uniform density as pbrt-v4
// does; sample() follows one walk and returns its weight, with that pdf() estimate as its density,
// used by the integrator only to weigh the strategies (multiple importance sampling stays
// unbiased because each strategy's weight is a fixed function of the direction pair). The walks'
// random numbers are hashes of the directions (eval, pdf) or of the sample values (sample), so
// the same call gives the same answer on every thread and backend.
//
// One departure from pbrt-v4: where a direction inside the slab could come from the walk or from
// the connection through the coat, the power heuristic weighs the walk's density against the
// connection's, the coat's refraction sampled from wi (coat.lobePdf(wi, -w)). pbrt-v4 takes the
// density of wi given -w there, a different measure: with it eval() came out 7% above what sample()
// reflects (a rough coat of alpha 0.3 over a Lambertian base; tests/materials/layered_bsdf_test.cpp
// holds them within 5 standard errors of each other).
//
// Transport: our interfaces scale radiance by 1 / eta^2 on refraction. The walk starts from wo
// (radiance), and the connection from wi is the adjoint (importance), whose refraction carries no
// scale: its weight is multiplied back by eta^2.
//
// Two-sided, as pbrt-v4's coated materials: seen from below, the coat is still on top.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "core/hash.h"
#include "core/henyey_greenstein.h"
#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "materials/bsdf.h"
#include "materials/conductor.h"
#include "materials/dielectric.h"
#include "materials/lambert.h"
#include "materials/microfacet.h"
#include "materials/rough_conductor.h"
#include "materials/rough_dielectric.h"

namespace penumbra {

struct LayeredBsdf {
    enum class Base : uint8_t { Diffuse, Conductor };

    // The coat: its index over the outside's, and its roughness (smooth below kSmoothAlpha).
    float eta = 1.5f;
    MicrofacetDistribution coatDistribution{0.0f, 0.0f, MicrofacetKind::Ggx};
    // The base: a Lambertian albedo, or a conductor's eta and k (relative to the outside, divided
    // by the coat's index where the walk meets it) and roughness.
    Base base = Base::Diffuse;
    Rgb baseAlbedo{0.5f, 0.5f, 0.5f};
    Rgb conductorEta{1.0f, 1.0f, 1.0f}, conductorK{0.0f, 0.0f, 0.0f};
    MicrofacetDistribution conductorDistribution{0.0f, 0.0f, MicrofacetKind::Ggx};
    // The slab between them.
    float thickness = 0.01f;
    Rgb albedo{0.0f, 0.0f, 0.0f};
    float g = 0.0f;
    // The walk: scattering events at most, and walks per eval() and pdf().
    int maxDepth = 10;
    int samples = 1;

    static constexpr BsdfFlags kFlags =
        BsdfFlags::Reflection | BsdfFlags::Diffuse | BsdfFlags::Glossy | BsdfFlags::Specular;

    Rgb eval(Vec3f wo, Vec3f wi, bool /*front*/) const {
        return withInterfaces<Rgb>(
            [&](const auto& coat, const auto& baseBsdf) { return evalWalk(coat, baseBsdf, wo, wi); });
    }
    float pdf(Vec3f wo, Vec3f wi, bool /*front*/) const {
        return withInterfaces<float>(
            [&](const auto& coat, const auto& baseBsdf) { return pdfEstimate(coat, baseBsdf, wo, wi); });
    }
    std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u, bool /*front*/) const {
        return withInterfaces<std::optional<BsdfSample>>(
            [&](const auto& coat, const auto& baseBsdf) { return sampleWalk(coat, baseBsdf, wo, uLobe, u); });
    }
    // The base's albedo, or the conductor's reflectance at normal incidence, as denoisers expect.
    Rgb reflectanceForAov() const {
        if (base == Base::Diffuse) return baseAlbedo;
        return fresnelComplex(1.0f, conductorEta, conductorK);
    }

private:
    // A small generator for the walk's own random numbers: SplitMix64 over a hashed seed.
    struct WalkRandom {
        uint64_t state;
        float operator()() {
            state += 0x9e3779b97f4a7c15ULL;
            return bitsToUnitFloat(uint32_t(mix64(state) >> 32));
        }
        Vec2f pair() {
            const float x = (*this)();
            return {x, (*this)()};
        }
    };
    static uint64_t bitsOf(Vec3f w) {
        return hashWords(std::bit_cast<uint32_t>(w.x), std::bit_cast<uint32_t>(w.y),
                         std::bit_cast<uint32_t>(w.z));
    }

    // The coat seen from the walk: wo's side decides whether light enters or leaves it, and a
    // rough coat narrower than kSmoothAlpha is the smooth one (as pbrt-v4's EffectivelySmooth).
    struct SmoothCoat {
        Dielectric interface;
        static constexpr bool kSpecular = true;
        std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const {
            return interface.sample(wo, uLobe, u, wo.z > 0.0f);
        }
        std::optional<BsdfSample> sampleLobe(Vec3f wo, Vec2f, bool transmission) const {
            return interface.sampleLobe(wo, transmission, wo.z > 0.0f);
        }
        Rgb eval(Vec3f, Vec3f) const { return Rgb(0.0f); }
        float pdf(Vec3f, Vec3f) const { return 0.0f; }
        float lobePdf(Vec3f, Vec3f) const { return 0.0f; }
    };
    struct RoughCoat {
        RoughDielectric interface;
        static constexpr bool kSpecular = false;
        std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const {
            return interface.sample(wo, uLobe, u, wo.z > 0.0f);
        }
        std::optional<BsdfSample> sampleLobe(Vec3f wo, Vec2f u, bool transmission) const {
            return interface.sampleLobe(wo, u, transmission, wo.z > 0.0f);
        }
        Rgb eval(Vec3f wo, Vec3f wi) const { return interface.eval(wo, wi, wo.z > 0.0f); }
        float pdf(Vec3f wo, Vec3f wi) const { return interface.pdf(wo, wi, wo.z > 0.0f); }
        float lobePdf(Vec3f wo, Vec3f wi) const { return interface.lobePdf(wo, wi, wo.z > 0.0f); }
    };
    // The base seen from inside the slab (it only reflects).
    template <class Model, bool kIsSpecular>
    struct Reflector {
        Model model;
        static constexpr bool kSpecular = kIsSpecular;
        std::optional<BsdfSample> sample(Vec3f wo, float uLobe, Vec2f u) const {
            return model.sample(wo, uLobe, u, true);
        }
        Rgb eval(Vec3f wo, Vec3f wi) const { return model.eval(wo, wi, true); }
        float pdf(Vec3f wo, Vec3f wi) const { return model.pdf(wo, wi, true); }
    };

    static bool isSmooth(const MicrofacetDistribution& d) {
        return std::max(d.alphaX, d.alphaY) < kSmoothAlpha;
    }

    // Calls f(coat, base) with the interfaces this material has at this point.
    template <class R, class F>
    R withInterfaces(F&& f) const {
        auto withBase = [&](const auto& coat) -> R {
            if (base == Base::Diffuse) return f(coat, Reflector<Lambert, false>{Lambert{baseAlbedo}});
            const Rgb etaInCoat = conductorEta / eta, kInCoat = conductorK / eta;
            if (isSmooth(conductorDistribution))
                return f(coat, Reflector<Conductor, true>{Conductor{etaInCoat, kInCoat}});
            return f(coat, Reflector<RoughConductor, false>{
                               RoughConductor{etaInCoat, kInCoat, conductorDistribution}});
        };
        if (isSmooth(coatDistribution) || eta == 1.0f) return withBase(SmoothCoat{Dielectric{eta}});
        RoughDielectric rough;
        rough.eta = eta;
        rough.distribution = coatDistribution;
        return withBase(RoughCoat{rough});
    }

    // Transmittance of the slab over a height dz along w.
    static float transmittance(float dz, Vec3f w) {
        if (std::abs(dz) <= std::numeric_limits<float>::min()) return 1.0f;
        return std::exp(-std::abs(dz / w.z));
    }
    bool scatters() const { return albedo.maxComponent() > 0.0f; }

    // The coat's refraction from wi into the slab, as the adjoint walk needs it: its weight with
    // the radiance scale 1 / eta^2 taken back out.
    template <class Coat>
    static std::optional<BsdfSample> importanceRefraction(const Coat& coat, Vec3f wi, WalkRandom& r) {
        std::optional<BsdfSample> s = coat.sampleLobe(wi, r.pair(), true);
        if (!s || s->wi.z == 0.0f) return std::nullopt;
        s->weight *= s->eta * s->eta;
        return s;
    }

    template <class Coat, class BaseBsdf>
    Rgb evalWalk(const Coat& coat, const BaseBsdf& baseBsdf, Vec3f wo, Vec3f wi) const {
        if (wo.z < 0.0f) {  // two-sided: the coat is on top whichever side wo is on
            wo = -wo;
            wi = -wi;
        }
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return Rgb(0.0f);                       // the base is opaque
        if (Coat::kSpecular && BaseBsdf::kSpecular && !scatters()) return Rgb(0.0f);  // every path a delta
        Rgb f = coat.eval(wo, wi) * float(samples);  // the coat's own reflection
        WalkRandom r{hashCombine(bitsOf(wo), bitsOf(wi))};
        const HenyeyGreenstein phase{g};
        for (int s = 0; s < samples; ++s) {
            std::optional<BsdfSample> wos = coat.sampleLobe(wo, r.pair(), true);
            if (!wos || wos->wi.z == 0.0f) continue;
            const std::optional<BsdfSample> wis = importanceRefraction(coat, wi, r);
            if (!wis) continue;
            // wis's weight is f |cos| / pdf: what a connection through it needs, but for the cosine.
            const float wisCos = std::abs(wis->wi.z);
            Rgb beta = wos->weight;
            float z = thickness;  // the coat is at z = thickness, the base at 0
            Vec3f w = wos->wi;
            for (int depth = 0; depth < maxDepth; ++depth) {
                if (depth > 3 && beta.maxComponent() < 0.25f) {  // Russian roulette
                    const float q = std::max(0.0f, 1.0f - beta.maxComponent());
                    if (r() < q) break;
                    beta = beta / (1.0f - q);
                }
                if (!scatters()) {
                    z = z == thickness ? 0.0f : thickness;
                    beta = beta * transmittance(thickness, w);
                } else {
                    const float dz = -std::log1p(-r()) * std::abs(w.z);
                    const float zNext = w.z > 0.0f ? z + dz : z - dz;
                    if (zNext == z) continue;
                    if (0.0f < zNext && zNext < thickness) {
                        // Scattered in the slab: connect to wi through the coat, then scatter on.
                        float weight = 1.0f;
                        if constexpr (!Coat::kSpecular)
                            weight = powerHeuristic(wis->pdf, phase.pdf(-w, -wis->wi));
                        f += beta * albedo * wis->weight *
                             (phase.p(-w, -wis->wi) * weight * transmittance(zNext - thickness, wis->wi) /
                              wisCos);
                        const PhaseSample ps = phase.sample(-w, r.pair());
                        if (!(ps.pdf > 0.0f) || ps.wi.z == 0.0f) continue;
                        beta = beta * albedo;
                        w = ps.wi;
                        z = zNext;
                        if constexpr (!Coat::kSpecular) {
                            if (w.z > 0.0f) {
                                const Rgb fExit = coat.eval(-w, wi);
                                if (fExit.maxComponent() > 0.0f)
                                    f += beta * fExit *
                                         (powerHeuristic(ps.pdf, coat.lobePdf(wi, -w)) *
                                          transmittance(zNext - thickness, ps.wi));
                            }
                        }
                        continue;
                    }
                    z = std::clamp(zNext, 0.0f, thickness);
                }
                if (z == thickness) {  // back at the coat: reflected into the slab
                    const std::optional<BsdfSample> bs = coat.sampleLobe(-w, r.pair(), false);
                    if (!bs || bs->wi.z == 0.0f) break;
                    beta = beta * bs->weight;
                    w = bs->wi;
                    continue;
                }
                // At the base: connect to wi through the coat, then reflect.
                if constexpr (!BaseBsdf::kSpecular) {
                    float weight = 1.0f;
                    if constexpr (!Coat::kSpecular)
                        weight = powerHeuristic(wis->pdf, baseBsdf.pdf(-w, -wis->wi));
                    f += beta * baseBsdf.eval(-w, -wis->wi) * wis->weight *
                         (weight * transmittance(thickness, wis->wi));
                }
                const float uLobe = r();
                const std::optional<BsdfSample> bs = baseBsdf.sample(-w, uLobe, r.pair());
                if (!bs || bs->wi.z == 0.0f) break;
                beta = beta * bs->weight;
                w = bs->wi;
                if constexpr (!Coat::kSpecular) {
                    const Rgb fExit = coat.eval(-w, wi);
                    if (fExit.maxComponent() > 0.0f) {
                        float weight = 1.0f;
                        if constexpr (!BaseBsdf::kSpecular)  // against the connection's density
                            weight = powerHeuristic(bs->pdf, coat.lobePdf(wi, -w));
                        f += beta * fExit * (weight * transmittance(thickness, bs->wi));
                    }
                }
            }
        }
        return f / float(samples);
    }

    template <class Coat, class BaseBsdf>
    float pdfEstimate(const Coat& coat, const BaseBsdf& baseBsdf, Vec3f wo, Vec3f wi) const {
        if (wo.z < 0.0f) {
            wo = -wo;
            wi = -wi;
        }
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
        if (Coat::kSpecular && BaseBsdf::kSpecular && !scatters()) return 0.0f;
        float sum = float(samples) * coat.lobePdf(wo, wi);  // the coat's reflection
        WalkRandom r{hashCombine(bitsOf(wi), bitsOf(wo))};
        for (int s = 0; s < samples; ++s) {
            // Transmission, reflection at the base, transmission: the density of the middle
            // event between the two refracted directions, or (a rough coat) the mean of two
            // estimates of the whole, weighed by the power heuristic.
            const std::optional<BsdfSample> wos = coat.sampleLobe(wo, r.pair(), true);
            const std::optional<BsdfSample> wis = coat.sampleLobe(wi, r.pair(), true);
            if (!wos || !wis || wos->wi.z == 0.0f || wis->wi.z == 0.0f) continue;
            if constexpr (Coat::kSpecular) {
                sum += baseBsdf.pdf(-wos->wi, -wis->wi);
            } else {
                const float uLobe = r();
                const std::optional<BsdfSample> rs = baseBsdf.sample(-wos->wi, uLobe, r.pair());
                if (!rs) continue;
                if constexpr (BaseBsdf::kSpecular) {
                    sum += coat.pdf(-rs->wi, wi);
                } else {
                    const float rPdf = baseBsdf.pdf(-wos->wi, -wis->wi);
                    sum += powerHeuristic(wis->pdf, rPdf) * rPdf;
                    const float tPdf = coat.pdf(-rs->wi, wi);
                    sum += powerHeuristic(rs->pdf, tPdf) * tPdf;
                }
            }
        }
        // Mixed with the uniform density, as pbrt-v4: never 0 where the BSDF may not be.
        return 0.1f * (1.0f / (4.0f * kPi)) + 0.9f * (sum / float(samples));
    }

    template <class Coat, class BaseBsdf>
    std::optional<BsdfSample> sampleWalk(const Coat& coat, const BaseBsdf& baseBsdf, Vec3f wo, float uLobe,
                                         Vec2f u) const {
        const bool flip = wo.z < 0.0f;
        if (flip) wo = -wo;
        if (!(wo.z > 0.0f)) return std::nullopt;
        std::optional<BsdfSample> first = coat.sample(wo, uLobe, u);
        if (!first || first->wi.z == 0.0f) return std::nullopt;
        auto leave = [&](BsdfSample s) {
            if (flip) s.wi = -s.wi;
            s.eta = 1.0f;
            return s;
        };
        if (first->wi.z > 0.0f) {  // reflected by the coat
            if (!first->isSpecular()) first->pdf = pdfEstimate(coat, baseBsdf, wo, first->wi);
            return leave(*first);
        }
        WalkRandom r{hashWords(bitsOf(wo), std::bit_cast<uint32_t>(uLobe), std::bit_cast<uint32_t>(u.x),
                               std::bit_cast<uint32_t>(u.y))};
        const HenyeyGreenstein phase{g};
        Rgb beta = first->weight;
        bool specularPath = first->isSpecular();
        float z = thickness;
        Vec3f w = first->wi;
        for (int depth = 0; depth < maxDepth; ++depth) {
            if (depth > 3 && beta.maxComponent() < 0.25f) {  // Russian roulette
                const float q = std::max(0.0f, 1.0f - beta.maxComponent());
                if (r() < q) return std::nullopt;
                beta = beta / (1.0f - q);
            }
            if (w.z == 0.0f) return std::nullopt;
            if (scatters()) {
                const float dz = -std::log1p(-r()) * std::abs(w.z);
                const float zNext = w.z > 0.0f ? z + dz : z - dz;
                if (zNext == z) return std::nullopt;
                if (0.0f < zNext && zNext < thickness) {
                    const PhaseSample ps = phase.sample(-w, r.pair());
                    if (!(ps.pdf > 0.0f) || ps.wi.z == 0.0f) return std::nullopt;
                    beta = beta * albedo;
                    specularPath = false;
                    w = ps.wi;
                    z = zNext;
                    continue;
                }
                z = std::clamp(zNext, 0.0f, thickness);
            } else {
                z = z == thickness ? 0.0f : thickness;
                beta = beta * transmittance(thickness, w);
            }
            const float uNext = r();
            const std::optional<BsdfSample> bs =
                z == 0.0f ? baseBsdf.sample(-w, uNext, r.pair()) : coat.sample(-w, uNext, r.pair());
            if (!bs || bs->wi.z == 0.0f) return std::nullopt;
            beta = beta * bs->weight;
            specularPath = specularPath && bs->isSpecular();
            w = bs->wi;
            if (z == thickness && w.z > 0.0f) {  // out through the coat
                if (!beta.isFinite()) return std::nullopt;
                BsdfSample out{w, beta, 1.0f, BsdfFlags::Reflection | BsdfFlags::Specular};
                if (!specularPath) {
                    out.flags = BsdfFlags::Reflection | BsdfFlags::Glossy;
                    out.pdf = pdfEstimate(coat, baseBsdf, wo, w);
                }
                return leave(out);
            }
        }
        return std::nullopt;
    }
};

}  // namespace penumbra
