// The volumetric path tracer, for scenes with participating media (Scene::hasMedia): null-
// scattering path tracing (Miller, Georgiev and Jarosz 2019, "A Null-Scattering Path Integral
// Formulation of Light Transport"), as pbrt-v4's VolPathIntegrator does it. Scenes without media
// keep the surface integrator (path_integrator.h), whose images and speed this leaves unchanged.
//
// Along each segment in a medium, delta tracking against the medium's majorants samples tentative
// collisions (media/medium.h); each is an absorption (the path ends), a real scattering (a path
// vertex: next-event estimation and a phase-function sample) or a null collision (the path goes
// on), chosen by the coefficients' shares of the majorant. Shadow rays go through homogeneous media
// with their exact transmittance and through other media by ratio tracking, through medium
// boundaries (the `interface` material), and are blocked by any other surface. A boundary is no
// path vertex: rays cross it unchanged, without counting a bounce.
//
// In a homogeneous medium, next-event estimation has a second strategy besides the scattering
// distance delta tracking samples: per segment, a light point chosen at the segment's start and a
// distance sampled equiangularly towards it (Kulla and Fajardo 2012, as Cycles does), where light
// from a lamp in fog concentrates (EquiangularSegment). The balance heuristic weighs it with the
// other two (distance sampling with light sampling, and with phase sampling).
//
// Colour: the densities of a path differ per channel in a chromatic medium. The path keeps, per
// channel, its sampling density and its light-sampling density each divided by the density with
// which it was actually sampled (pbrt-v4's rescaled r_u and r_l), and a contribution is divided by
// their average over the channels: one-sample MIS (balance heuristic) over the three channels'
// distance sampling, the channel that samples (the hero) chosen uniformly per path, and over light
// and BSDF or phase sampling. Without media this is the balance heuristic where the surface
// integrator takes the power heuristic: the two agree in expectation, not bit for bit.
//
// Subsurface scattering is a random walk: a subsurface material is a dielectric boundary around a
// homogeneous medium (scenes/material_interior.h), and a path that refracts in scatters inside by
// the delta tracking above until it is absorbed or leaves through the boundary (diffusely:
// materials/subsurface_boundary.h, where light is sampled again). Within the walk no light is
// sampled (the boundary would block every shadow ray: emission found through it counts in full)
// and its events count as one bounce against max_depth, bounded apart (kMaxWalkVertices), as
// Cycles' random walk does.
//
// Sample dimensions: the surface dimensions are drawn per scattering vertex as in the surface
// integrator (a medium vertex uses LightPosition and BsdfDirection like a surface vertex); the
// media's per segment (core/sampler.h's MediumDim: Distance, Event and their SampleStreams), so
// that every decision has a named dimension and no value is used twice along a path.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/equiangular.h"
#include "media/medium.h"
#include "renderer/path_integrator.h"

namespace penumbra {

namespace detail {

// Rays that cross more medium boundaries than this in one segment are given up (as blocked):
// a boundary seen edge-on repeatedly must not loop forever.
inline constexpr int kMaxBoundaryCrossings = 256;

// A random walk inside a subsurface material (Scene::isMaterialInterior) ends, as absorbed, after
// this many scattering events and reflections off its boundary from inside; they do not count
// against the integrator's max_depth (Cycles bounds its walks at 256 steps).
inline constexpr uint32_t kMaxWalkVertices = 1024;

// A segment through a homogeneous medium on which next-event estimation has a second strategy:
// equiangular sampling of the scattering distance towards a point of a light chosen at the segment's
// start (core/equiangular.h), besides the distance that delta tracking samples (here distance
// sampling, since the majorant is sigma_t). Both estimate the light scattered once along the
// segment; they and phase-function sampling are weighed by the balance heuristic over all three and
// the three channels (as pbrt-v4's rL and rU do for two). Only for lights whose point does not
// depend on the reference (LightModelType's kPointIndependentOfReference: point, spot,
// goniometric, triangle lights), so that a point can be chosen before the distance.
struct EquiangularSegment {
    bool active = false;
    Vec3f origin, direction;  // direction unit
    float tEnd = 0.0f;
    Rgb rU0{1.0f};  // the path's rU at the segment's start
    Rgb sigmaT{0.0f}, sigmaS{0.0f};
    int hero = 0;

    // Per channel, the prefix's density over the hero's density of distance sampling a scattering
    // at distance t: the equiangular strategy's relative density but for the light's density and
    // the equiangular pdf (rE carries it until an emitter's hit gives those).
    Rgb densityRatioAt(float t) const {
        const float heroDistancePdf = std::exp(-sigmaT[hero] * t) * sigmaS[hero];
        return heroDistancePdf > 0.0f ? rU0 / heroDistancePdf : Rgb(0.0f);
    }
    // Per channel, the equiangular strategy's density of a scattering at distance t towards the
    // light point y (solid-angle density lightPdf at the scattering point, the light chosen at the
    // segment's start) over the hero's density of distance sampling scattering there: the term it
    // adds to rL.
    Rgb relativeDensity(float t, Vec3f y, float lightPdf) const {
        const float pE = EquiangularDistance(origin, direction, tEnd, y).pdf(t);
        if (!(pE > 0.0f)) return Rgb(0.0f);
        return densityRatioAt(t) * (lightPdf * pE);
    }
};

// What a path carries through media and surfaces.
struct VolumetricPath {
    Radiance radiance{0.0f};
    Radiance beta{1.0f};     // throughput over the hero channel's sampling density
    Rgb rU{1.0f}, rL{1.0f};  // per channel: sampling and light-sampling densities over the hero's
    // Per channel, after a medium vertex on an equiangular segment: the equiangular strategy's
    // density over the hero's but for the light's density and the equiangular pdf (known once an
    // emitter is hit), updated as rL; 0 elsewhere.
    Rgb rE{0.0f};
    EquiangularSegment vertexSegment;  // that segment
    float vertexDistance = 0.0f;       // and the vertex's distance along it
    float etaScale = 1.0f;             // as PathState::etaScale
    bool specularBounce = true;        // the previous vertex was the camera or a delta lobe
    Vec3f previousPosition;
    Vec3f previousNormal;  // 0 at a medium vertex (LightSet::choose takes no normal there)
    uint32_t medium = MediumInterface::kVacuum;
    int hero = 0;               // the channel whose majorants sample distances
    int depth = 0;              // bounces so far (surface or medium scattering events, a walk's as one)
    uint32_t vertex = 0;        // scattering events so far, every one: the surface dimensions' index
    uint32_t walkVertices = 0;  // events of the current walk inside a subsurface material
    uint32_t segment = 0;       // ray segments so far: the media's sample dimensions' index
};

inline bool anyPositive(Rgb c) { return c.r > 0.0f || c.g > 0.0f || c.b > 0.0f; }

// The null-collision coefficient sigma_maj - sigma_t, never negative.
inline Rgb nullCoefficient(const MediumProperties& mp, Rgb sigmaMaj) {
    return {std::max(0.0f, sigmaMaj.r - mp.sigmaA.r - mp.sigmaS.r),
            std::max(0.0f, sigmaMaj.g - mp.sigmaA.g - mp.sigmaS.g),
            std::max(0.0f, sigmaMaj.b - mp.sigmaA.b - mp.sigmaS.b)};
}

// Emission found by a sampled direction (a hit or an escape), weighted against light sampling.
// `lightPdf` is called only when the weight needs it; `equiangularPdf` (the light's density and the
// equiangular distance's, for the hit point) only after a vertex on an equiangular segment.
template <typename LightPdf, typename EquiangularPdf>
void addFoundEmission(const IntegratorContext& ctx, VolumetricPath& path, Rgb emitted, LightPdf&& lightPdf,
                      EquiangularPdf&& equiangularPdf) {
    if (emitted.isBlack()) return;
    if (path.specularBounce || ctx.strategy == LightStrategy::Bsdf) {
        path.radiance += path.beta * emitted / path.rU.average();
        return;
    }
    const float pdf = lightPdf();
    if (ctx.strategy == LightStrategy::Light) {
        // What light sampling cannot reach stays with the sampled direction.
        if (!(pdf > 0.0f)) path.radiance += path.beta * emitted / path.rU.average();
        return;
    }
    Rgb denominator = path.rU + path.rL * pdf;
    if (anyPositive(path.rE)) denominator += path.rE * equiangularPdf();
    path.radiance += path.beta * emitted / denominator.average();
}

// Transmittance along a shadow ray to its end (ray.tfar: 1 - 2^-20 towards a point, infinity
// towards a direction) through media and medium boundaries; 0 when a surface other than a
// boundary blocks it. Through a homogeneous medium it is exact (Beer-Lambert: nothing sampled);
// through others it is estimated by ratio tracking, and rL and rU are updated with the tracking's
// densities. (Ratio tracking against a homogeneous medium's own sigma_t, its majorant, has no null
// collisions and so estimates 0 or 1: pbrt-v4 does that; Cycles, as here, does not.)
template <TraversalBackend Accel>
Rgb transmittanceAlong(const Accel& accel, const IntegratorContext& ctx, Ray ray, TriangleLeft left,
                       uint32_t medium, int hero, SampleStream& stream, Rgb& rL, Rgb& rU, RayCounters& rays) {
    const Scene& scene = *ctx.scene;
    const bool towardsPoint = std::isfinite(ray.tfar);
    const Vec3f target = ray.origin + ray.direction;
    Rgb transmitted(1.0f);
    for (int crossing = 0;; ++crossing) {
        ++rays.shadow;
        Hit hit;
        const bool found = accel.intersect(ray, hit, left);
        SurfaceInteraction si;
        if (found) {
            si = Accel::kReportsCanonicalHits || !ctx.canonicalHits
                     ? resolveHit<true>(scene, ray, hit, ctx.faceFrames)
                     : resolveHit<false>(scene, ray, hit, ctx.faceFrames);
            if (!scene.materials[si.material].isInterface()) return Rgb(0.0f);
        }
        if (medium != MediumInterface::kVacuum) {
            const float directionLength = length(ray.direction);
            const float tEnd = (found ? hit.t : ray.tfar) * directionLength;
            if (const auto* homogeneous = std::get_if<HomogeneousMedium>(&scene.media[medium])) {
                transmitted *= transmittance(homogeneous->sigmaA + homogeneous->sigmaS, tEnd);
                if (!anyPositive(transmitted)) return Rgb(0.0f);
            } else {
                const Rgb tMaj = sampleFreeFlight(
                    scene.media[medium], ray.origin, ray.direction / directionLength, tEnd, hero,
                    stream.next(), [&] { return stream.next(); },
                    [&](float, Vec3f, const MediumProperties& mp, Rgb sigmaMaj, Rgb tMajHere) {
                        const Rgb sigmaN = nullCoefficient(mp, sigmaMaj);
                        const float pdf = tMajHere[hero] * sigmaMaj[hero];
                        transmitted *= tMajHere * sigmaN / pdf;
                        rL *= tMajHere * sigmaMaj / pdf;
                        rU *= tMajHere * sigmaN / pdf;
                        // Russian roulette once the estimate is small (pbrt-v4's threshold and odds).
                        const Rgb estimate = transmitted / (rL + rU).average();
                        if (estimate.maxComponent() < 0.05f) {
                            if (stream.next() < 0.75f)
                                transmitted = Rgb(0.0f);
                            else
                                transmitted *= 1.0f / 0.25f;
                        }
                        return anyPositive(transmitted);
                    });
                if (!anyPositive(transmitted) || !(tMaj[hero] > 0.0f)) return Rgb(0.0f);
                const Rgb ratio = tMaj / tMaj[hero];
                transmitted *= ratio;
                rL *= ratio;
                rU *= ratio;
            }
        }
        if (!found) return transmitted;
        if (crossing >= kMaxBoundaryCrossings) return Rgb(0.0f);
        // Through the boundary: on into the medium on its far side.
        const float cosGeometric = dot(ray.direction, si.geometricNormal);
        medium = scene.mediaOf(si.shape).mediumAlong(ray.direction, si.geometricNormal, medium);
        ray.origin = offsetRayOrigin(si.position, si.positionError,
                                     cosGeometric >= 0.0f ? si.geometricNormal : -si.geometricNormal);
        left = si.shape.isTriangle() ? TriangleLeft{hit.geomId, hit.primId} : TriangleLeft{};
        if (towardsPoint) ray.direction = target - ray.origin;
    }
}

// Next-event estimation's light sample at a vertex at `p` (geometric normal `n`, 0 in a medium):
// the choice of light (into `chosen`, where given: the light and its probability) and the point on
// it, or nothing.
inline std::optional<LightSample> sampleLightAt(const IntegratorContext& ctx, const PixelSample& sample,
                                                uint32_t depth, Vec3f p, Vec3f n,
                                                LightSet::Choice* chosen = nullptr) {
    const LightSet& lights = *ctx.lights;
    Vec2f uLight{0.5f, 0.5f};
    LightSet::Choice light{0, 1.0f};
    if (lights.drawsSampleValues()) {
        uLight = sample.get2DUnfrozen(Dim::LightPosition, depth);
        light = lights.choose(uLight, p, n);
        if (sample.isFrozen(Dim::LightPosition)) [[unlikely]]
            uLight = {0.5f, 0.5f};
    }
    if (chosen) *chosen = light;
    auto ls = lights.sample(light, p, uLight);
    if (ls && ls->radiance.isBlack()) return std::nullopt;
    return ls;
}

// The contribution of a light sample whose path to the light has throughput `beta` and scattering
// value `f` (BSDF times cosine, or phase function), once the shadow ray's transmittance is known:
// rL and rU are, per channel, the densities of the strategies that sample the light's point (light
// sampling) and its direction from the vertex (BSDF or phase sampling) over the hero's sampling
// density, before the shadow ray's.
template <TraversalBackend Accel>
Radiance lightContribution(const Accel& accel, const IntegratorContext& ctx, Radiance beta, Rgb rL, Rgb rU,
                           int hero, const LightSample& ls, Rgb f, const Ray& shadowRay, TriangleLeft left,
                           uint32_t medium, SampleStream& stream, RayCounters& rays) {
    const Rgb transmitted =
        transmittanceAlong(accel, ctx, shadowRay, left, medium, hero, stream, rL, rU, rays);
    if (transmitted.isBlack()) return Radiance(0.0f);
    return beta * f * transmitted * ls.radiance / (rL + rU).average();
}

// The density of sampling the light sample's direction by the BSDF or phase function (`scatterPdf`)
// as next-event estimation weighs it: none for delta lights, which it cannot hit, or when only
// light sampling counts.
inline float scatterDensityAgainst(const IntegratorContext& ctx, const LightSample& ls, float scatterPdf) {
    return ls.isDelta || ctx.strategy == LightStrategy::Light ? 0.0f : scatterPdf;
}

// A shadow ray from the medium point `p` to the light sample `ls`.
inline Ray shadowRayFromMedium(Vec3f p, const LightSample& ls, float time) {
    Ray shadow;
    shadow.origin = p;
    shadow.time = time;
    if (std::isinf(ls.distance)) {
        shadow.direction = ls.direction;
    } else {
        Vec3f target = ls.point;
        if (!ls.isDelta)
            target = offsetRayOrigin(ls.point, ls.pointError, faceForward(ls.lightNormal, -ls.direction));
        shadow.direction = target - p;
        shadow.tfar = 1.0f - 0x1p-20f;
    }
    return shadow;
}

// Whether the segment through `medium` gets equiangular light samples (EquiangularSegment).
inline bool samplesEquiangularly(const IntegratorContext& ctx, const VolumetricPath& path,
                                 const MediumModel& medium) {
    const auto* homogeneous = std::get_if<HomogeneousMedium>(&medium);
    return homogeneous && ctx.strategy == LightStrategy::Mis && path.depth < ctx.maxDepth &&
           ctx.lights->hasPointIndependentLights() && anyPositive(homogeneous->sigmaS);
}

// The equiangular light sample of a segment (EquiangularSegment): a light and a point on it chosen
// at the segment's start, a distance towards the point, next-event estimation there.
template <TraversalBackend Accel>
Radiance equiangularLightSample(const Accel& accel, const IntegratorContext& ctx, const PixelSample& sample,
                                const VolumetricPath& path, const EquiangularSegment& segment,
                                const HenyeyGreenstein& phase, uint32_t medium, float time,
                                RayCounters& rays) {
    const LightSet& lights = *ctx.lights;
    SampleStream stream = sample.stream(MediumDim::EquiangularLight, path.segment);
    Vec2f uLight{stream.next(), stream.next()};
    LightSet::Choice choice{0, 1.0f};
    if (lights.drawsSampleValues()) choice = lights.choose(uLight, segment.origin, Vec3f{});
    if (!lights.isPointIndependentOfReference(choice.light)) return Radiance(0.0f);
    const auto atStart = lights.sample(choice, segment.origin, uLight);
    if (!atStart) return Radiance(0.0f);
    const EquiangularDistance distance(segment.origin, segment.direction, segment.tEnd, atStart->point);
    if (!distance.valid()) return Radiance(0.0f);
    const float t = std::clamp(distance.sample(sample.get1D(MediumDim::EquiangularDistance, path.segment)),
                               0.0f, segment.tEnd);
    const float pE = distance.pdf(t);
    const Vec3f p = segment.origin + segment.direction * t;
    const auto ls = lights.sample(choice, p, uLight);  // the same point, seen from p
    if (!ls || ls->radiance.isBlack() || !(pE > 0.0f) || !(ls->pdf > 0.0f)) return Radiance(0.0f);
    // The densities of the other two strategies for this point and direction: distance sampling with
    // the light chosen at p, then light sampling or phase sampling there.
    const Rgb scattered = transmittance(segment.sigmaT, t) * segment.sigmaS;
    const float distanceLightPdf =
        ls->pdf * lights.choiceProbability(choice.light, p, Vec3f{}) / choice.probability;
    const float phaseValue = phase.p(-segment.direction, ls->direction);
    const Rgb rL = segment.rU0 * (ls->pdf * pE) + segment.rU0 * scattered * distanceLightPdf;
    const Rgb rU = segment.rU0 * scattered * scatterDensityAgainst(ctx, *ls, phaseValue);
    return lightContribution(accel, ctx, path.beta * scattered, rL, rU, path.hero, *ls, Rgb(phaseValue),
                             shadowRayFromMedium(p, *ls, time), TriangleLeft{}, medium, stream, rays);
}

// Russian roulette on the throughput freed of the channels' densities and of refraction's scale.
inline bool survivesVolumetricRoulette(const IntegratorContext& ctx, const PixelSample& sample,
                                       VolumetricPath& path) {
    if (path.depth < ctx.rouletteStartDepth) return true;
    const float survival =
        std::min(1.0f, std::sqrt((path.beta * (path.etaScale / path.rU.average())).maxComponent()));
    if (survival < 1.0f) {
        if (sample.get1D(Dim::RussianRoulette, path.vertex) >= survival) return false;
        path.beta *= 1.0f / survival;
    }
    return true;
}

}  // namespace detail

// Radiance arriving along the camera ray `ray` for the sample `sample`, through media: see the
// file's comment. `firstHit` as for estimateRadiance (the first surface that is not a boundary).
template <TraversalBackend Accel>
Radiance estimateRadianceThroughMedia(const Accel& accel, const IntegratorContext& ctx, Ray ray,
                                      const PixelSample& sample, RayCounters& rays, FirstHitAovs* firstHit) {
    using namespace detail;
    const Scene& scene = *ctx.scene;
    const LightSet& lights = *ctx.lights;
    VolumetricPath path;
    path.medium = ctx.cameraMedium;
    path.hero = std::min(2, int(sample.get1D(MediumDim::Channel, 0) * 3.0f));
    path.previousPosition = ray.origin;
    TexturedMaterialSlot textured;
    TriangleLeft left;
    bool sawSurface = false;
    float cameraDistance = 0.0f;  // the camera ray's length up to the last boundary it crossed
    // The medium of the current walk when its subsurface material's coefficients are textured: the
    // interior's, with the coefficients found where the walk entered.
    std::optional<MediumModel> walkMedium;
    auto currentMedium = [&]() -> const MediumModel& {
        return walkMedium ? *walkMedium : scene.media[path.medium];
    };
    ++rays.primary;

    for (;; ++path.segment) {
        Hit hit;
        const bool found = accel.intersect(ray, hit, left);
        SurfaceInteraction si;
        if (found)
            si = Accel::kReportsCanonicalHits || !ctx.canonicalHits
                     ? resolveHit<true>(scene, ray, hit, ctx.faceFrames)
                     : resolveHit<false>(scene, ray, hit, ctx.faceFrames);
        const float directionLength = length(ray.direction);
        const Vec3f direction = ray.direction / directionLength;

        if (path.medium != MediumInterface::kVacuum) {
            bool scattered = false, ended = false;
            SampleStream distances = sample.stream(MediumDim::Distance, path.segment);
            SampleStream events = sample.stream(MediumDim::Event, path.segment);
            float uEvent = sample.get1D(MediumDim::Event, path.segment);
            const float tEnd = found ? hit.t * directionLength : std::numeric_limits<float>::infinity();
            EquiangularSegment segment;
            // Inside a subsurface material: a walk, whose shadow rays its boundary would block.
            const bool inWalk = scene.isMaterialInterior(path.medium);
            if (!inWalk && samplesEquiangularly(ctx, path, scene.media[path.medium])) {
                const auto& homogeneous = std::get<HomogeneousMedium>(scene.media[path.medium]);
                segment = {true,
                           ray.origin,
                           direction,
                           tEnd,
                           path.rU,
                           homogeneous.sigmaA + homogeneous.sigmaS,
                           homogeneous.sigmaS,
                           path.hero};
                path.radiance += equiangularLightSample(accel, ctx, sample, path, segment, homogeneous.phase,
                                                        path.medium, ray.time, rays);
            }
            const Rgb tMaj = sampleFreeFlight(
                currentMedium(), ray.origin, direction, tEnd, path.hero,
                sample.get1D(MediumDim::Distance, path.segment), [&] { return distances.next(); },
                [&](float t, Vec3f p, const MediumProperties& mp, Rgb sigmaMaj, Rgb tMajHere) {
                    const int h = path.hero;
                    if (path.depth < ctx.maxDepth && !mp.emission.isBlack()) {
                        const float pdf = sigmaMaj[h] * tMajHere[h];
                        const Rgb rE = path.rU * sigmaMaj * tMajHere / pdf;
                        if (anyPositive(rE))
                            path.radiance +=
                                path.beta * tMajHere / pdf * mp.sigmaA * mp.emission / rE.average();
                    }
                    const Rgb sigmaN = nullCoefficient(mp, sigmaMaj);
                    const float pAbsorb = mp.sigmaA[h] / sigmaMaj[h], pScatter = mp.sigmaS[h] / sigmaMaj[h];
                    const float pNull = sigmaN[h] / sigmaMaj[h];
                    // The three add up to 1 but for rounding, which must not pick an event of probability 0.
                    const float u = uEvent * (pAbsorb + pScatter + pNull);
                    uEvent = events.next();
                    if (u < pAbsorb) {
                        ended = true;
                        return false;
                    }
                    if (u < pAbsorb + pScatter) {
                        const uint32_t vertexDepth = path.vertex++;
                        if (inWalk ? ++path.walkVertices > kMaxWalkVertices : path.depth++ >= ctx.maxDepth) {
                            ended = true;
                            return false;
                        }
                        const float pdf = tMajHere[h] * mp.sigmaS[h];
                        path.beta *= tMajHere * mp.sigmaS / pdf;
                        path.rU *= tMajHere * mp.sigmaS / pdf;
                        if (path.beta.isBlack() || path.rU.isBlack()) {
                            ended = true;
                            return false;
                        }
                        // A medium vertex: light sampling, then the phase function's sample.
                        const Vec3f wo = -direction;
                        if (!inWalk && !lights.empty() && ctx.strategy != LightStrategy::Bsdf) {
                            LightSet::Choice light{0, 1.0f};
                            if (const auto ls = sampleLightAt(ctx, sample, vertexDepth, p, Vec3f{}, &light)) {
                                // The equiangular strategy's density for this light point, if it has one.
                                Rgb equiangularDensity(0.0f);
                                if (segment.active && lights.isPointIndependentOfReference(light.light))
                                    equiangularDensity = segment.relativeDensity(
                                        t, ls->point,
                                        ls->pdf *
                                            lights.choiceProbability(light.light, segment.origin, Vec3f{}) /
                                            light.probability);
                                const float phase = mp.phase.p(wo, ls->direction);
                                SampleStream shadowStream =
                                    sample.stream(MediumDim::ShadowTransmittance, path.segment);
                                path.radiance += lightContribution(
                                    accel, ctx, path.beta, path.rU * ls->pdf + equiangularDensity,
                                    path.rU * scatterDensityAgainst(ctx, *ls, phase), path.hero, *ls,
                                    Rgb(phase), shadowRayFromMedium(p, *ls, ray.time), TriangleLeft{},
                                    path.medium, shadowStream, rays);
                            }
                        }
                        const PhaseSample ps =
                            mp.phase.sample(wo, sample.get2D(Dim::BsdfDirection, vertexDepth));
                        path.rL = path.rU / ps.pdf;  // the sample's weight p / pdf is 1
                        // An emitter the phase sample hits weighs the equiangular strategy too.
                        path.rE = segment.active ? segment.densityRatioAt(t) / ps.pdf : Rgb(0.0f);
                        path.vertexSegment = segment;
                        path.vertexDistance = t;
                        path.specularBounce = inWalk;  // no light sampled: found emission counts in full
                        path.previousPosition = p;
                        path.previousNormal = Vec3f{};
                        ray.origin = p;
                        ray.direction = ps.wi;
                        ray.tnear = 0.0f;
                        ray.tfar = std::numeric_limits<float>::infinity();
                        scattered = true;
                        if (!survivesVolumetricRoulette(ctx, sample, path)) ended = true;
                        return false;
                    }
                    // A null collision: on along the ray.
                    const float pdf = tMajHere[h] * sigmaN[h];
                    if (!(pdf > 0.0f)) {
                        ended = true;
                        return false;
                    }
                    path.beta *= tMajHere * sigmaN / pdf;
                    path.rU *= tMajHere * sigmaN / pdf;
                    path.rL *= tMajHere * sigmaMaj / pdf;
                    path.rE *= tMajHere * sigmaMaj / pdf;
                    if (path.beta.isBlack() || path.rU.isBlack()) {
                        ended = true;
                        return false;
                    }
                    return true;
                });
            if (ended) break;
            if (scattered) {
                left = TriangleLeft{};
                ++rays.extension;
                continue;
            }
            if (!(tMaj[path.hero] > 0.0f)) break;
            const Rgb ratio = tMaj / tMaj[path.hero];
            path.beta *= ratio;
            path.rU *= ratio;
            path.rL *= ratio;
            path.rE *= ratio;
        }

        if (!found) {
            if (lights.hasEnvironment())
                addFoundEmission(
                    ctx, path, lights.environmentRadiance(ray.direction),
                    [&] {
                        return lights.pdfOfEnvironment(path.previousPosition, path.previousNormal,
                                                       ray.direction);
                    },
                    [] { return 0.0f; });
            break;
        }
        left = si.shape.isTriangle() ? TriangleLeft{hit.geomId, hit.primId} : TriangleLeft{};
        const Vec3f wo = -direction;
        const Material* shaded = &scene.materials[si.material];
        if (shaded->isInterface()) {
            // A medium boundary: the ray goes on unchanged, into the medium beyond it.
            cameraDistance += hit.t * directionLength;
            const float cosGeometric = dot(ray.direction, si.geometricNormal);
            const uint32_t before = path.medium;
            path.medium = scene.mediaOf(si.shape).mediumAlong(ray.direction, si.geometricNormal, path.medium);
            if (path.medium != before) walkMedium.reset();
            ray.origin = offsetRayOrigin(si.position, si.positionError,
                                         cosGeometric >= 0.0f ? si.geometricNormal : -si.geometricNormal);
            ray.tnear = 0.0f;
            ray.tfar = std::numeric_limits<float>::infinity();
            ++rays.extension;
            continue;
        }
        // A mix never includes an interface (the scene loader refuses it): resolved after the test.
        if (shaded->variesOverSurface()) [[unlikely]]
            shaded = shadeAtPoint(*shaded, ctx, si, wo, ray.time, textured);
        const SurfaceVertex vertex{si, *shaded, wo, dot(wo, si.geometricNormal) > 0.0f};
        if (!sawSurface) {
            sawSurface = true;
            if (firstHit && path.depth == 0)
                *firstHit = {true, cameraDistance + hit.t * directionLength, si.shadingNormal,
                             vertex.material.albedo()};
        }
        // Beer-Lambert absorption inside a dielectric that declares it (path_integrator.h).
        if (!vertex.woAbove) {
            const Rgb sigma = vertex.material.interiorAbsorption();
            if (!sigma.isBlack()) path.beta *= transmittance(sigma, hit.t * directionLength);
        }
        addFoundEmission(
            ctx, path, lights.emitted(si, wo),
            [&] { return lights.pdfOfHit(path.previousPosition, path.previousNormal, si); },
            [&] {
                const EquiangularSegment& segment = path.vertexSegment;
                return lights.pdfOfHitChosenAt(segment.origin, path.previousPosition, si) *
                       EquiangularDistance(segment.origin, segment.direction, segment.tEnd, si.position)
                           .pdf(path.vertexDistance);
            });
        // The boundary of a subsurface material seen from inside: part of the walk.
        const bool inWalk = scene.isMaterialInterior(path.medium);
        if (inWalk ? ++path.walkVertices > kMaxWalkVertices : path.depth++ >= ctx.maxDepth) break;
        const uint32_t vertexDepth = path.vertex++;

        const LocalFrame local(si, wo, *ctx.scene);
        // Light sampling at the surface.
        if (!lights.empty() && !vertex.material.isPurelySpecular() && ctx.strategy != LightStrategy::Bsdf)
            if (const auto ls = sampleLightAt(ctx, sample, vertexDepth, si.position, si.geometricNormal)) {
                const Vec3f wiLocal = local.lanes.toLocal(ls->direction);
                const bool reflects = local.woLocal.z * wiLocal.z > 0.0f;
                const float cosLight = dot(ls->direction, si.geometricNormal);
                if (((cosLight > 0.0f) == vertex.woAbove) == reflects) {
                    const Rgb f =
                        vertex.material.eval(local.woLocal, wiLocal, vertex.woAbove) * std::abs(wiLocal.z);
                    if (!f.isBlack()) {
                        const Ray shadow = spawnShadowRay(si, local.leaveDistance, *ls, cosLight, ray.time);
                        const uint32_t shadowMedium = scene.mediaOf(si.shape).mediumAlong(
                            ls->direction, si.geometricNormal, path.medium);
                        SampleStream shadowStream =
                            sample.stream(MediumDim::ShadowTransmittance, path.segment);
                        const float bsdfPdf = vertex.material.pdf(local.woLocal, wiLocal, vertex.woAbove);
                        path.radiance +=
                            lightContribution(accel, ctx, path.beta, path.rU * ls->pdf,
                                              path.rU * scatterDensityAgainst(ctx, *ls, bsdfPdf), path.hero,
                                              *ls, f, shadow, left, shadowMedium, shadowStream, rays);
                    }
                }
            }

        // The continuation: a BSDF sample.
        const float uLobe =
            vertex.material.usesLobeSample() ? sample.get1D(Dim::BsdfLobe, vertexDepth) : 0.5f;
        const auto bs = vertex.material.sample(local.woLocal, uLobe,
                                               sample.get2D(Dim::BsdfDirection, vertexDepth), vertex.woAbove);
        if (!bs) break;
        const Vec3f wi = local.lanes.toWorld(bs->wi);
        const float cosWi = dot(wi, si.geometricNormal);
        if (((cosWi > 0.0f) != vertex.woAbove) != bs->isTransmission()) break;
        path.beta *= bs->weight;
        if (bs->isTransmission()) path.etaScale *= bs->eta * bs->eta;
        if (path.beta.isBlack()) break;
        path.rL = path.rU / bs->pdf;
        path.rE = Rgb(0.0f);
        path.specularBounce = bs->isSpecular();
        path.previousPosition = si.position;
        path.previousNormal = si.geometricNormal;
        if (!survivesVolumetricRoulette(ctx, sample, path)) break;
        const bool walked = scene.isMaterialInterior(path.medium);
        path.medium = scene.mediaOf(si.shape).mediumAlong(wi, si.geometricNormal, path.medium);
        if (!scene.isMaterialInterior(path.medium)) {
            path.walkVertices = 0;
            walkMedium.reset();
        } else if (!walked) {
            walkMedium.reset();
            if (const std::optional<std::pair<Rgb, Rgb>> k = vertex.material.texturedInterior())
                [[unlikely]] {
                HomogeneousMedium interior = std::get<HomogeneousMedium>(scene.media[path.medium]);
                interior.sigmaA = k->first;
                interior.sigmaS = k->second;
                walkMedium = interior;
            }
        }
        continueRay(ray, si, local.leaveDistance, wi, cosWi);
        ++rays.extension;
    }
    return path.radiance;
}

}  // namespace penumbra
