// The unidirectional path tracer: at each vertex, next-event estimation towards one light chosen
// by power, combined by multiple importance sampling (power heuristic) with the BSDF-sampled
// continuation; Russian roulette after a configurable depth.
//
// Russian roulette: from bounce `rouletteStartDepth` on, a path continues with probability
// q = min(1, sqrt(max channel of its throughput)) and its throughput is divided by q when it does,
// so the estimator stays unbiased and paths carrying little energy end early. The square root (as
// Cycles takes it) ends them later than q = throughput would: on a glass sphere's caustic, paths
// through the glass were cut at their second interface with half their weight left, which cost
// error at the same time per sample (bench/README.md, "time_to_error.py"). The throughput used for q
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
// calls are direct, never virtual.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <optional>

#include "accel/traversal.h"
#include "core/check.h"
#include "core/frame.h"
#include "core/ray.h"
#include "core/ray_offset.h"
#include "core/sampler.h"
#include "film/aov.h"
#include "geometry/face_frames.h"
#include "geometry/surface_derivatives.h"
#include "geometry/surface_interaction.h"
#include "lights/light_set.h"
#include "materials/material.h"
#include "scenes/scene.h"
#include "textures/texture_footprint.h"

namespace penumbra {

// The integrator's radiance type (and its throughput's): RGB. A spectral mode would make it a few
// sampled wavelengths' values (README, "How it is built").
using Radiance = Rgb;

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
    LightStrategy strategy = LightStrategy::Mis;
    const FaceFrames* faceFrames =
        nullptr;                // optional: the still meshes' normals and frames, computed beforehand
    CameraFootprint footprint;  // for textures that filter by footprint (textures/texture_footprint.h)
    // The medium camera rays start in (renderer/volumetric_path_integrator.h).
    uint32_t cameraMedium = MediumInterface::kVacuum;

    // The context of a scene's render: its lights, and its integrator settings.
    static IntegratorContext forScene(const Scene& scene, const LightSet& lights,
                                      const FaceFrames* faceFrames = nullptr,
                                      const CameraFootprint& footprint = {}) {
        return {&scene,
                &lights,
                scene.integrator.maxDepth,
                scene.integrator.rouletteStartDepth,
                scene.settings.canonicalHits,
                scene.integrator.strategy,
                faceFrames,
                footprint,
                scene.cameraMedium};
    }
};

// What the backend found for a camera ray that the caller traced already (with others, as a packet).
struct TracedRay {
    bool found = false;
    Hit hit;
};

namespace detail {

// For PENUMBRA_CHECK: a direction the BSDF made unit and a frame rotated is off by a few float
// ulps (~1e-7 each); 1e-3 allows that many times over and still catches a direction that was
// never normalized or a frame that is not orthonormal.
inline bool isUnit(Vec3f v) { return std::abs(length(v) - 1.0f) < 1e-3f; }

// Turns `ray` into the ray leaving `si` in direction `direction`, offset off the surface on that
// side by `leaveDistance` (offsetDistance at si, computed once for the vertex's rays), at the same
// time (`cosGeometric`: dot(direction, si.geometricNormal), which the caller has computed already).
// Written in place, field by field (bench/README.md, "Speed tricks").
[[gnu::always_inline]] inline void continueRay(Ray& ray, const SurfaceInteraction& si, float leaveDistance,
                                               Vec3f direction, float cosGeometric) {
    const Vec3f side = cosGeometric >= 0.0f ? si.geometricNormal : -si.geometricNormal;
    ray.origin = offsetAlong(si.position, side, leaveDistance);
    ray.direction = direction;
    ray.tnear = 0.0f;
    ray.tfar = std::numeric_limits<float>::infinity();
}

// The weight of emission that a BSDF sample found (after a vertex that is not a delta one), against
// next-event estimation's density for the same point: the power heuristic under MIS; all of it
// when light sampling is off; none when light sampling alone accounts for that emitter (what it
// cannot sample, lightPdf = 0, stays with the BSDF sample).
[[gnu::always_inline]] inline float hitWeight(LightStrategy strategy, float bsdfPdf, float lightPdf) {
    if (strategy == LightStrategy::Mis) return powerHeuristic(bsdfPdf, lightPdf);
    return strategy == LightStrategy::Bsdf || !(lightPdf > 0.0f) ? 1.0f : 0.0f;
}

// Room for a textured material's evaluated copy (Material::at), filled only at textured hits. A
// std::optional<Material> in its place cost every path, textured or not: GCC zero-filled all its
// 88 bytes (a `rep stos`) at the start of each path (bench/README.md, "Speed tricks").
class TexturedMaterialSlot {
public:
    TexturedMaterialSlot() {}
    TexturedMaterialSlot(const TexturedMaterialSlot&) = delete;
    TexturedMaterialSlot& operator=(const TexturedMaterialSlot&) = delete;
    ~TexturedMaterialSlot() {
        if (full_) material().~Material();
    }
    const Material& fill(Material value) {
        if (full_) {
            material() = std::move(value);
        } else {
            ::new (static_cast<void*>(bytes_)) Material(std::move(value));
            full_ = true;
        }
        return material();
    }

private:
    Material& material() { return *std::launder(reinterpret_cast<Material*>(bytes_)); }
    alignas(Material) unsigned char bytes_[sizeof(Material)];
    bool full_ = false;
};

// A textured material at `si`: its bump or normal map turns the shading normal there (whose
// precomputed frame then no longer applies), and its textured parameters are evaluated into
// `slot` (Material::at); the pixel footprint and the surface derivatives are computed once, and only
// when a texture filters by the footprint or a map needs them. Returns the material to shade with.
inline const Material* shadeTextured(const Material& material, const IntegratorContext& ctx,
                                     SurfaceInteraction& si, float time, TexturedMaterialSlot& slot) {
    TextureQuery query;
    query.uv = si.uv;
    query.p = si.position;
    query.n = si.geometricNormal;
    const NormalPerturbation* perturbation = material.perturbation();
    if (perturbation || material.needsFootprint()) {
        const SurfaceDerivatives d = surfaceDerivatives(*ctx.scene, si, time);
        const TextureQuery footprint =
            textureQueryAt(ctx.footprint, si.position, si.geometricNormal, si.uv, d.dpdu, d.dpdv);
        if (perturbation) {
            si.shadingNormal = perturbedNormal(*perturbation, footprint, si.shadingNormal, d.dpdu, d.dpdv,
                                               si.geometricNormal);
            si.shadingFrame = nullptr;
        }
        if (material.needsFootprint()) query = footprint;
    }
    if (material.texturedParameters()->empty()) return &material;
    return &slot.fill(material.at(query));
}

// The material to shade `si` with, seen along wo, for a material that varies over its surface
// (Material::variesOverSurface): a mix's choice there (materials/material_mix.h), then textured
// there when it is textured, then a fiber's offset set. Out of line: scenes with neither mixes nor textures
// never call it.
[[gnu::noinline]] inline const Material* shadeAtPoint(const Material& material, const IntegratorContext& ctx,
                                                      SurfaceInteraction& si, Vec3f wo, float time,
                                                      TexturedMaterialSlot& slot) {
    const Material* shaded = &material;
    if (material.mix())
        shaded = &ctx.scene->materials[resolveMix(ctx.scene->materials, si.material, si.position, wo, si.uv,
                                                  si.geometricNormal)];
    if (shaded->isTextured()) shaded = shadeTextured(*shaded, ctx, si, time, slot);
    if (shaded->isFiber()) {
        // The fiber's frame is the curve's, its normal facing the ray (the BSDF models the round
        // fiber itself, so a cylinder curve's turned normal would count the offset twice), and
        // h = 2 v - 1 is where across it the ray arrived, along the frame's second axis.
        si.shadingNormal = si.geometricNormal;
        si.shadingFrame = nullptr;
        shaded = &slot.fill(shaded->withFiberOffset(std::clamp(2.0f * si.uv.y - 1.0f, -1.0f, 1.0f)));
    }
    return shaded;
}

// A shadow ray from `si` to a point on a light; both ends are moved off their surfaces, so the
// segment [0, 1) of the unnormalized direction may be tested in full. `leaveDistance` and
// `cosGeometric` as for continueRay.
[[gnu::always_inline]] inline Ray spawnShadowRay(const SurfaceInteraction& si, float leaveDistance,
                                                 const LightSample& ls, float cosGeometric, float time) {
    const Vec3f side = cosGeometric >= 0.0f ? si.geometricNormal : -si.geometricNormal;
    Ray ray;
    ray.origin = offsetAlong(si.position, side, leaveDistance);
    ray.time = time;
    if (std::isinf(ls.distance)) {
        ray.direction = ls.direction;
        return ray;
    }
    Vec3f target = ls.point;
    if (!ls.isDelta)
        target = offsetRayOrigin(ls.point, ls.pointError, faceForward(ls.lightNormal, -ls.direction));
    ray.direction = target - ray.origin;
    ray.tfar = 1.0f - 0x1p-20f;
    return ray;
}

// What a path carries from one vertex to the next.
struct PathState {
    Radiance radiance{0.0f};    // gathered so far
    Radiance throughput{1.0f};  // the product of the BSDF weights (over their densities) so far
    float etaScale = 1.0f;      // product of eta^2 over the refractions so far (see Russian roulette above)
    // The previous vertex, against whose BSDF sample emission found by this segment is weighted.
    float previousBsdfPdf = 0.0f;
    bool previousWasDelta = true;  // the camera vertex: emitters seen directly get full weight
    Vec3f previousPosition;
    Vec3f previousNormal;  // its geometric normal: the light choice's probability there depends on it
};

// A surface vertex as its steps see it: the hit, its material and where the path arrived from.
struct SurfaceVertex {
    const SurfaceInteraction& si;
    const Material& material;
    Vec3f wo;      // unit, towards where the path came from
    bool woAbove;  // whether wo is on the geometric normal's side
};

// The vertex's shading frame and the offset of the rays that leave it.
struct LocalFrame {
    [[gnu::always_inline]] LocalFrame(const SurfaceInteraction& si, Vec3f wo, const SceneGeometry& scene)
        : lanes(si.shadingFrame                      ? *si.shadingFrame
                : si.shape.kind == ShapeKind::Curves ? curveShadingFrame(scene, si)
                                                     : Frame::fromNormal(si.shadingNormal)),
          woLocal(lanes.toLocal(wo)),
          leaveDistance(offsetDistance(si.position, si.positionError, si.geometricNormal)) {}
    FrameLanes lanes;
    Vec3f woLocal;
    float leaveDistance;  // how far the vertex's shadow and bounce rays start off the surface (either side)
};

// Next-event estimation's shadow ray, traced after the continuation's BSDF sample, and what it
// adds when nothing blocks it.
struct PendingShadowRay {
    bool cast = false;
    Ray ray;
    Radiance contribution;
};

// Step: the path escaped along `ray`; the environment's light, weighted against its NEE.
[[gnu::always_inline]] inline void addEscapedLight(const IntegratorContext& ctx, const LightSet& lights,
                                                   const Ray& ray, PathState& path) {
    if (!lights.hasEnvironment()) return;
    const Radiance environment = lights.environmentRadiance(ray.direction);
    if (environment.isBlack()) return;
    const float weight =
        path.previousWasDelta
            ? 1.0f
            : hitWeight(ctx.strategy, path.previousBsdfPdf,
                        lights.pdfOfEnvironment(path.previousPosition, path.previousNormal, ray.direction));
    path.radiance += path.throughput * environment * weight;
}

// Step: what the segment that arrived at the vertex passed through. A segment that reached the
// back side of a surface travelled inside its material: Beer-Lambert absorption by its interior.
// (Scenes with participating media are rendered by volumetric_path_integrator.h instead.)
[[gnu::always_inline]] inline void attenuateAlongSegment(const SurfaceVertex& v, const Ray& ray, float hitT,
                                                         PathState& path) {
    if (v.woAbove) return;
    const Rgb sigma = v.material.interiorAbsorption();
    if (sigma.isBlack()) return;
    const float distance = hitT * length(ray.direction);
    path.throughput *=
        Rgb(std::exp(-sigma.r * distance), std::exp(-sigma.g * distance), std::exp(-sigma.b * distance));
}

// Step: emission at the hit, found by the previous vertex's BSDF sample; weighted against NEE.
[[gnu::always_inline]] inline void addEmissionAtHit(const IntegratorContext& ctx, const LightSet& lights,
                                                    const SurfaceVertex& v, PathState& path) {
    const Radiance emitted = lights.emitted(v.si, v.wo);
    if (emitted.isBlack()) return;
    const float weight = path.previousWasDelta
                             ? 1.0f
                             : hitWeight(ctx.strategy, path.previousBsdfPdf,
                                         lights.pdfOfHit(path.previousPosition, path.previousNormal, v.si));
    path.radiance += path.throughput * emitted * weight;
}

// Step: direct light (next-event estimation): one light, a point on it, and the shadow ray that
// would carry its contribution.
[[gnu::always_inline]] inline PendingShadowRay sampleDirectLight(
    const IntegratorContext& ctx, const LightSet& lights, const PixelSample& sample, uint32_t bounce,
    const SurfaceVertex& v, const LocalFrame& local, const PathState& path, float time) {
    PendingShadowRay shadow;
    if (lights.empty() || v.material.isPurelySpecular() || ctx.strategy == LightStrategy::Bsdf) return shadow;
    // Sample values that would not be used are not drawn (each dimension is keyed on its own, so
    // skipping one leaves the others as they are). One 2D value chooses the light and then the
    // point on it (LightSet::choose); frozen, it fixes the point on each light but not the choice
    // (README, `--freeze`).
    Vec2f uLight{0.5f, 0.5f};
    LightSet::Choice light{0, 1.0f};
    if (lights.drawsSampleValues()) {
        uLight = sample.get2DUnfrozen(Dim::LightPosition, bounce);
        light = lights.choose(uLight, v.si.position, v.si.geometricNormal);
        if (sample.isFrozen(Dim::LightPosition)) [[unlikely]]
            uLight = {0.5f, 0.5f};
    }
    const auto ls = lights.sample(light, v.si.position, uLight);
    const Vec3f wiLocal = ls ? local.lanes.toLocal(ls->direction) : Vec3f{};
    // Reflection needs the light on wo's side of the geometric surface, transmission on the other.
    const bool reflects = local.woLocal.z * wiLocal.z > 0.0f;
    const float cosLight = ls ? dot(ls->direction, v.si.geometricNormal) : 0.0f;
    if (ls && !ls->radiance.isBlack() && ((cosLight > 0.0f) == v.woAbove) == reflects) {
        const Rgb f = v.material.eval(local.woLocal, wiLocal, v.woAbove) * std::abs(wiLocal.z);
        if (!f.isBlack()) {
            PENUMBRA_CHECK(ls->pdf > 0.0f, "a light sample has a positive density");
            shadow.cast = true;
            shadow.ray = spawnShadowRay(v.si, local.leaveDistance, *ls, cosLight, time);
            const float weight =
                ls->isDelta || ctx.strategy == LightStrategy::Light
                    ? 1.0f
                    : powerHeuristic(ls->pdf, v.material.pdf(local.woLocal, wiLocal, v.woAbove));
            shadow.contribution = path.throughput * f * ls->radiance * (weight / ls->pdf);
        }
    }
    return shadow;
}

// Step: Russian roulette, after the continuation has updated the throughput. Whether the path
// survives (its throughput then divided by the survival probability).
[[gnu::always_inline]] inline bool survivesRoulette(const IntegratorContext& ctx, const PixelSample& sample,
                                                    uint32_t bounce, PathState& path) {
    if (int(bounce) + 1 < ctx.rouletteStartDepth) return true;
    // A path that survives for certain draws no sample (u < 1 never ends it).
    const float survival = std::min(1.0f, std::sqrt((path.throughput * path.etaScale).maxComponent()));
    if (survival < 1.0f) {
        if (sample.get1D(Dim::RussianRoulette, bounce) >= survival) return false;
        path.throughput *= 1.0f / survival;
    }
    return true;
}

// Step: continuation: a BSDF sample for the next segment, then Russian roulette. Whether the path
// goes on, and if so its next segment in `ray` and its new throughput (the pending shadow ray's
// contribution has the old one).
[[gnu::always_inline]] inline bool continuePath(const IntegratorContext& ctx, const LightSet& lights,
                                                const PixelSample& sample, uint32_t bounce, Vec2f uDirection,
                                                const SurfaceVertex& v, const LocalFrame& local,
                                                PathState& path, Ray& ray) {
    const float uLobe = v.material.usesLobeSample() ? sample.get1D(Dim::BsdfLobe, bounce) : 0.5f;
    const auto bs = v.material.sample(local.woLocal, uLobe, uDirection, v.woAbove);
    if (!bs) return false;
    PENUMBRA_CHECK(bs->pdf > 0.0f, "a BSDF sample has a positive density");
    const Vec3f wi = local.lanes.toWorld(bs->wi);
    PENUMBRA_CHECK(isUnit(wi), "a BSDF sample's direction has unit length");
    const float cosWi = dot(wi, v.si.geometricNormal);
    // A reflection that crosses the geometric surface, or a transmission that does not.
    if (((cosWi > 0.0f) != v.woAbove) != bs->isTransmission()) return false;
    path.throughput *= bs->weight;
    if (bs->isTransmission()) path.etaScale *= bs->eta * bs->eta;
    if (path.throughput.isBlack()) return false;
    path.previousBsdfPdf = bs->pdf;
    path.previousWasDelta = bs->isSpecular();
    path.previousPosition = v.si.position;
    path.previousNormal = v.si.geometricNormal;
    if (!survivesRoulette(ctx, sample, bounce, path)) return false;
    PENUMBRA_CHECK(path.throughput.isFinite() && path.throughput.minComponent() >= 0.0f,
                   "a path's throughput is finite and non-negative");
    // The ray past the last vertex only looks for emission; without emitters it could hit, it is
    // not traced (as Embree's pathtracer counts path length).
    if (int(bounce) + 1 >= ctx.maxDepth && !lights.emitsAlongRays()) return false;
    continueRay(ray, v.si, local.leaveDistance, wi, cosWi);
    return true;
}

}  // namespace detail

// Radiance arriving along `ray` (a camera ray) for the sample `sample`: the path's vertices, each
// taking the steps above in this order: what the segment passed through, emission at the hit,
// direct light (its shadow ray left pending), continuation (with Russian roulette), then the
// pending shadow ray. The steps are always inlined: as calls they cost more instructions
// (bench/README.md, "Speed tricks"). When `firstHit` is given it receives the first hit's AOVs
// (hit = false when the ray leaves the scene). When `traced` is given it is what tracing `ray`
// found, and the ray is not traced again.
template <TraversalBackend Accel>
Radiance estimateRadiance(const Accel& accel, const IntegratorContext& ctx, Ray ray,
                          const PixelSample& sample, RayCounters& rays, FirstHitAovs* firstHit = nullptr,
                          const TracedRay* traced = nullptr) {
    const LightSet& lights = *ctx.lights;
    detail::PathState path;
    path.previousPosition = ray.origin;
    // A textured material's values at the current vertex (Material::at); untouched otherwise.
    detail::TexturedMaterialSlot textured;
    // The triangle the current vertex lies on, which its bounce and shadow rays leave.
    TriangleLeft left;
    ++rays.primary;

    for (uint32_t bounce = 0;; ++bounce) {
        // Drawn before the ray is traced although it is used after (bench/README.md, "Speed tricks").
        const Vec2f uDirection = sample.get2D(Dim::BsdfDirection, bounce);
        Hit hit;
        bool found;
        if (bounce == 0 && traced) {
            found = traced->found;
            hit = traced->hit;
        } else {
            found = accel.intersect(ray, hit, left);
        }
        if (!found) {
            detail::addEscapedLight(ctx, lights, ray, path);
            break;
        }
        SurfaceInteraction si = Accel::kReportsCanonicalHits || !ctx.canonicalHits
                                    ? resolveHit<true>(*ctx.scene, ray, hit, ctx.faceFrames)
                                    : resolveHit<false>(*ctx.scene, ray, hit, ctx.faceFrames);
        left = si.shape.isTriangle() ? TriangleLeft{hit.geomId, hit.primId} : TriangleLeft{};
        // Bounce rays leave in unit directions (the BSDF's, turned into the world); only the
        // caller's camera ray may not be.
        const Vec3f wo = bounce == 0 ? -normalize(ray.direction) : -ray.direction;
        const Material* shaded = &ctx.scene->materials[si.material];
        if (shaded->variesOverSurface()) [[unlikely]]
            shaded = detail::shadeAtPoint(*shaded, ctx, si, wo, ray.time, textured);
        const detail::SurfaceVertex vertex{si, *shaded, wo, dot(wo, si.geometricNormal) > 0.0f};
        if (bounce == 0 && firstHit)
            *firstHit = {true, hit.t * length(ray.direction), si.shadingNormal, vertex.material.albedo()};

        detail::attenuateAlongSegment(vertex, ray, hit.t, path);
        detail::addEmissionAtHit(ctx, lights, vertex, path);
        if (int(bounce) >= ctx.maxDepth) break;

        const detail::LocalFrame local(si, wo, *ctx.scene);
        // The shadow ray is traced after the continuation's BSDF sample, not before: the two are
        // independent (bench/README.md, "Speed tricks").
        const detail::PendingShadowRay shadow =
            detail::sampleDirectLight(ctx, lights, sample, bounce, vertex, local, path, ray.time);
        const bool continues =
            detail::continuePath(ctx, lights, sample, bounce, uDirection, vertex, local, path, ray);
        if (shadow.cast) {
            ++rays.shadow;
            if (!accel.occluded(shadow.ray, left)) path.radiance += shadow.contribution;
        }
        if (!continues) break;
        ++rays.extension;
    }
    return path.radiance;
}

}  // namespace penumbra
