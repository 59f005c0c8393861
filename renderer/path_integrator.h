// The unidirectional path tracer: at each vertex, next-event estimation towards one light chosen
// by power, combined by multiple importance sampling (power heuristic) with the BSDF-sampled
// continuation; Russian roulette after a configurable depth.
//
// Russian roulette: from bounce `rouletteStartDepth` on, a path continues with probability
// q = min(1, max channel of its throughput) and its throughput is divided by q when it does, so the
// estimator stays unbiased and paths carrying little energy end early. The throughput used for q
// leaves out the radiance scale 1 / eta^2 of refractions (pbrt-v4's etaScale): inside glass the
// throughput is 1 / eta^2 smaller without carrying less energy, and it gets the factor back on leaving.
//
// Sides: a BSDF lobe that reflects (wo and wi on the same side of the shading frame) is only
// followed, or connected to a light, when wi is also on wo's side of the geometric surface, and a
// lobe that transmits only when wi is on the other side; this keeps shading normals from leaking
// light through surfaces. Materials are told on which side of the geometric surface wo lies: that
// decides whether light enters or leaves a dielectric, and one-sided materials are black from
// the back.
//
// Absorption: a path segment that reaches a surface from its back side travelled inside that
// surface's material; when the material has an absorbing interior (a dielectric with Beer-Lambert
// absorption), the throughput is multiplied by exp(-sigma_a * segment length). Closed shapes must
// therefore have their front sides (geometric normals) facing out.
//
// The integrator is a template over the traversal backend (accel/traversal.h) so that the per-ray
// calls are direct, never virtual. Each vertex of a path takes the same named steps, in this
// order: the emission found at the hit, the direct light (a shadow ray left pending), the
// continuation (BSDF sample and Russian roulette), then the pending shadow ray is traced.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "accel/traversal.h"
#include "core/check.h"
#include "core/frame.h"
#include "core/ray.h"
#include "core/ray_offset.h"
#include "core/sampler.h"
#include "film/aov.h"
#include "geometry/face_frames.h"
#include "geometry/surface_interaction.h"
#include "lights/light_set.h"
#include "materials/material.h"
#include "scenes/scene.h"

namespace penumbra {

struct RayCounters {
    uint64_t primary = 0, extension = 0, shadow = 0;
    uint64_t total() const { return primary + extension + shadow; }
    RayCounters& operator+=(const RayCounters& o) {
        primary += o.primary;
        extension += o.extension;
        shadow += o.shadow;
        return *this;
    }
};

struct IntegratorContext {
    const Scene* scene = nullptr;
    const LightSet* lights = nullptr;
    int maxDepth = 64;
    int rouletteStartDepth = 3;
    bool canonicalHits = true;  // RenderSettings::canonicalHits
    const FaceFrames* faceFrames = nullptr;  // optional: the still meshes' normals and frames, computed beforehand

    // The context of a scene's render: its lights, and its integrator settings.
    static IntegratorContext forScene(const Scene& scene, const LightSet& lights, const FaceFrames* faceFrames = nullptr) {
        return {&scene, &lights, scene.integrator.maxDepth, scene.integrator.rouletteStartDepth,
                scene.settings.canonicalHits, faceFrames};
    }
};

// What the backend found for a camera ray that the caller traced already (with others, as a packet).
struct TracedRay {
    bool found = false;
    Hit hit;
};

namespace detail {

// What a path carries from vertex to vertex.
struct PathState {
    Rgb radiance{0.0f};
    Rgb throughput{1.0f};
    float etaScale = 1.0f;  // product of eta^2 over the refractions so far (see Russian roulette above)
    // The previous vertex's BSDF sample, for the MIS weight of emission found by it.
    float previousBsdfPdf = 0.0f;
    bool previousWasSpecular = true;  // the camera vertex: emitters seen directly get full weight
    Vec3f previousPosition;
};

// A shadow ray whose contribution is added if nothing blocks it.
struct PendingShadowRay {
    bool pending = false;
    Ray ray;
    Rgb contribution;
};

// The shading point at a vertex, seen from the direction the path arrived from.
struct Vertex {
    SurfaceInteraction si;
    const Material* material;
    Vec3f wo;          // unit, towards where the path came from
    bool woAbove;      // wo on the front side of the geometric surface
    Frame frame;       // the shading frame
    Vec3f woLocal;
};

inline bool isUnit(Vec3f v) { return std::abs(length(v) - 1.0f) < 1e-3f; }

// Turns `ray` into the ray leaving `si` in direction `direction`, offset off the surface on that
// side, at the same time (`cosGeometric`: dot(direction, si.geometricNormal), which the caller has
// computed already). Written in place, field by field (bench/README.md: store forwarding).
inline void continueRay(Ray& ray, const SurfaceInteraction& si, Vec3f direction, float cosGeometric) {
    const Vec3f side = cosGeometric >= 0.0f ? si.geometricNormal : -si.geometricNormal;
    ray.origin = offsetRayOrigin(si.position, side);
    ray.direction = direction;
    ray.tnear = 0.0f;
    ray.tfar = std::numeric_limits<float>::infinity();
}

// A shadow ray from `si` to a point on a light; both ends are moved off their surfaces, so the
// segment [0, 1) of the unnormalized direction may be tested in full. `cosGeometric` as for continueRay.
inline Ray spawnShadowRay(const SurfaceInteraction& si, const LightSample& ls, float cosGeometric, float time) {
    const Vec3f side = cosGeometric >= 0.0f ? si.geometricNormal : -si.geometricNormal;
    Ray ray;
    ray.origin = offsetRayOrigin(si.position, side);
    ray.time = time;
    if (std::isinf(ls.distance)) {
        ray.direction = ls.direction;
        return ray;
    }
    Vec3f target = ls.point;
    if (!ls.isDelta) target = offsetRayOrigin(ls.point, faceForward(ls.lightNormal, -ls.direction));
    ray.direction = target - ray.origin;
    ray.tfar = 1.0f - 0x1p-20f;
    return ray;
}

// The background's radiance reaching a path that leaves the scene, weighted against its NEE.
[[gnu::always_inline]] inline void addEscapedRadiance(PathState& path, const LightSet& lights) {
    const Rgb background = lights.background();
    if (background.isBlack()) return;
    const float weight =
        path.previousWasSpecular ? 1.0f : powerHeuristic(path.previousBsdfPdf, lights.pdfOfBackground());
    path.radiance += path.throughput * background * weight;
}

// Beer-Lambert absorption along a segment that arrived at the back side of an absorbing interior.
[[gnu::always_inline]] inline void absorbAlongSegment(PathState& path, const Vertex& v, const Ray& ray, float t) {
    if (v.woAbove) return;
    const Rgb sigma = v.material->interiorAbsorption();
    if (sigma.isBlack()) return;
    const float distance = t * length(ray.direction);
    path.throughput *= Rgb(std::exp(-sigma.r * distance), std::exp(-sigma.g * distance),
                           std::exp(-sigma.b * distance));
}

// Emission at the hit, found by the previous vertex's BSDF sample: weighted against NEE.
[[gnu::always_inline]] inline void addEmissionAtHit(PathState& path, const LightSet& lights, const Vertex& v) {
    const Rgb emitted = lights.emitted(v.si, v.wo);
    if (emitted.isBlack()) return;
    const float weight = path.previousWasSpecular
                             ? 1.0f
                             : powerHeuristic(path.previousBsdfPdf, lights.pdfOfHit(path.previousPosition, v.si));
    path.radiance += path.throughput * emitted * weight;
}

// Next-event estimation: one light chosen by power, a point on it, and the shadow ray that decides
// whether its contribution (weighted against the BSDF sample by MIS) counts.
[[gnu::always_inline]] inline PendingShadowRay sampleDirectLight(const LightSet& lights, const PixelSample& sample,
                                                                 uint32_t bounce, const Vertex& v,
                                                                 const PathState& path, float time) {
    PendingShadowRay shadow;
    if (lights.empty() || v.material->isPurelySpecular()) return shadow;
    // Sample values that would not be used are not drawn (each dimension is keyed on its own, so
    // skipping one leaves the others as they are).
    const uint32_t light = lights.choose(lights.size() > 1 ? sample.get1D(Dim::LightChoice, bounce) : 0.5f);
    const auto ls = lights.sample(light, v.si.position,
                                  lights.isDelta(light) ? Vec2f{0.5f, 0.5f} : sample.get2D(Dim::LightPosition, bounce));
    const Vec3f wiLocal = ls ? v.frame.toLocal(ls->direction) : Vec3f{};
    // Reflection needs the light on wo's side of the geometric surface, transmission on the other.
    const bool reflects = v.woLocal.z * wiLocal.z > 0.0f;
    const float cosLight = ls ? dot(ls->direction, v.si.geometricNormal) : 0.0f;
    if (!ls || ls->radiance.isBlack() || ((cosLight > 0.0f) == v.woAbove) != reflects) return shadow;
    const Rgb f = v.material->eval(v.woLocal, wiLocal, v.woAbove) * std::abs(wiLocal.z);
    if (f.isBlack()) return shadow;
    PENUMBRA_CHECK(ls->pdf > 0.0f, "a light sample has a positive density");
    shadow.pending = true;
    shadow.ray = spawnShadowRay(v.si, *ls, cosLight, time);
    const float weight = ls->isDelta ? 1.0f : powerHeuristic(ls->pdf, v.material->pdf(v.woLocal, wiLocal, v.woAbove));
    shadow.contribution = path.throughput * f * ls->radiance * (weight / ls->pdf);
    return shadow;
}

// The continuation: a BSDF sample for the next segment, then Russian roulette. False when the path
// ends here; otherwise `ray` is the next segment and the path's throughput and MIS state are updated.
[[gnu::always_inline]] inline bool continuePath(const IntegratorContext& ctx, const PixelSample& sample,
                                                uint32_t bounce, Vec2f uDirection, const Vertex& v, PathState& path,
                                                Ray& ray) {
    const Material& material = *v.material;
    const float uLobe = material.usesLobeSample() ? sample.get1D(Dim::BsdfLobe, bounce) : 0.5f;
    const auto bs = material.sample(v.woLocal, uLobe, uDirection, v.woAbove);
    if (!bs) return false;
    PENUMBRA_CHECK(bs->pdf > 0.0f, "a BSDF sample has a positive density");
    const Vec3f wi = v.frame.toWorld(bs->wi);
    PENUMBRA_CHECK(isUnit(wi), "a BSDF sample's direction has unit length");
    const float cosWi = dot(wi, v.si.geometricNormal);
    // A reflection that crosses the geometric surface, or a transmission that does not.
    if (((cosWi > 0.0f) != v.woAbove) != bs->isTransmission()) return false;
    path.throughput *= bs->weight;
    if (bs->isTransmission()) path.etaScale *= bs->eta * bs->eta;
    if (path.throughput.isBlack()) return false;
    path.previousBsdfPdf = bs->pdf;
    path.previousWasSpecular = bs->isSpecular();
    path.previousPosition = v.si.position;

    if (int(bounce) + 1 >= ctx.rouletteStartDepth) {
        // A path that survives for certain draws no sample (u < 1 never ends it).
        const float survival = std::min(1.0f, (path.throughput * path.etaScale).maxComponent());
        if (survival < 1.0f) {
            if (sample.get1D(Dim::RussianRoulette, bounce) >= survival) return false;
            path.throughput *= 1.0f / survival;
        }
    }
    PENUMBRA_CHECK(path.throughput.isFinite() && path.throughput.minComponent() >= 0.0f,
                   "a path's throughput is finite and non-negative");
    // The ray past the last vertex only looks for emission; without emitters it could hit, it is
    // not traced (as Embree's pathtracer counts path length).
    if (int(bounce) + 1 >= ctx.maxDepth && !ctx.lights->emitsAlongRays()) return false;
    continueRay(ray, v.si, wi, cosWi);
    return true;
}

}  // namespace detail

// Radiance arriving along `ray` (a camera ray) for the sample `sample`. When `firstHit` is given
// it receives the first hit's AOVs (hit = false when the ray leaves the scene). When `traced` is
// given it is what tracing `ray` found, and the ray is not traced again.
template <TraversalBackend Accel>
Rgb estimateRadiance(const Accel& accel, const IntegratorContext& ctx, Ray ray, const PixelSample& sample,
                     RayCounters& rays, FirstHitAovs* firstHit = nullptr, const TracedRay* traced = nullptr) {
    const LightSet& lights = *ctx.lights;
    detail::PathState path;
    path.previousPosition = ray.origin;
    ++rays.primary;

    for (uint32_t bounce = 0;; ++bounce) {
        // Drawn before the ray is traced although it is used after (bench/README.md: latency).
        const Vec2f uDirection = sample.get2D(Dim::BsdfDirection, bounce);
        Hit hit;
        bool found;
        if (bounce == 0 && traced) {
            found = traced->found;
            hit = traced->hit;
        } else {
            found = accel.intersect(ray, hit);
        }
        if (!found) {
            detail::addEscapedRadiance(path, lights);
            break;
        }
        detail::Vertex v;
        v.si = Accel::kReportsCanonicalHits || !ctx.canonicalHits
                   ? resolveHit<true>(*ctx.scene, ray, hit, ctx.faceFrames)
                   : resolveHit<false>(*ctx.scene, ray, hit, ctx.faceFrames);
        // Bounce rays leave in unit directions (the BSDF's, turned into the world); only the
        // caller's camera ray may not be.
        v.wo = bounce == 0 ? -normalize(ray.direction) : -ray.direction;
        v.material = &ctx.scene->materials[v.si.material];
        v.woAbove = dot(v.wo, v.si.geometricNormal) > 0.0f;
        if (bounce == 0 && firstHit)
            *firstHit = {true, hit.t * length(ray.direction), v.si.shadingNormal, v.material->albedo()};

        detail::absorbAlongSegment(path, v, ray, hit.t);
        detail::addEmissionAtHit(path, lights, v);
        if (int(bounce) >= ctx.maxDepth) break;

        v.frame = v.si.shadingFrame ? *v.si.shadingFrame : Frame::fromNormal(v.si.shadingNormal);
        v.woLocal = v.frame.toLocal(v.wo);
        // The shadow ray is traced after the continuation's BSDF sample, not before: the two are
        // independent (bench/README.md: overlap).
        const detail::PendingShadowRay shadow = detail::sampleDirectLight(lights, sample, bounce, v, path, ray.time);
        const bool continues = detail::continuePath(ctx, sample, bounce, uDirection, v, path, ray);

        if (shadow.pending) {
            ++rays.shadow;
            if (!accel.occluded(shadow.ray)) path.radiance += shadow.contribution;
        }
        if (!continues) break;
        ++rays.extension;
    }
    return path.radiance;
}

}  // namespace penumbra
