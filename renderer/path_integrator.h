// The unidirectional path tracer: at each vertex, next-event estimation towards one light chosen
// by power, combined by multiple importance sampling (power heuristic) with the BSDF-sampled
// continuation; Russian roulette after a configurable depth.
//
// Russian roulette: from bounce `rouletteStartDepth` on, a path continues with probability
// q = min(1, sqrt(max channel of its throughput)) and its throughput is divided by q when it does,
// so the estimator stays unbiased and paths carrying little energy end early. The square root (as
// Cycles takes it) ends them later than q = throughput would: on a glass sphere's caustic, paths
// through the glass were cut at their second interface with half their weight left, which cost
// 15% more mean squared error at the same time per sample (bench/README.md). The throughput used for q
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
                footprint};
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

// The material at `si` with its textures evaluated there (Material::at), the footprint computed
// only when a texture filters by it. Out of line: untextured scenes never call it.
[[gnu::noinline]] inline Material texturedMaterial(const Material& material, const IntegratorContext& ctx,
                                                   const SurfaceInteraction& si, float time) {
    TextureQuery query;
    query.uv = si.uv;
    if (material.needsFootprint()) {
        const SurfaceDerivatives d = surfaceDerivatives(*ctx.scene, si, time);
        query = textureQueryAt(ctx.footprint, si.position, si.geometricNormal, si.uv, d.dpdu, d.dpdv);
    }
    return material.at(query);
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

}  // namespace detail

// Radiance arriving along `ray` (a camera ray) for the sample `sample`. Each vertex takes the
// steps named in the comments below in this order: emission at the hit, direct light (a shadow
// ray left pending), continuation, then the pending shadow ray. They stay one loop body rather
// than functions: as functions passing a vertex and a pending shadow ray by struct they cost 3%
// more instructions (bench/README.md, "Speed tricks"). When `firstHit` is given it receives the
// first hit's AOVs (hit = false when the ray leaves the scene). When `traced` is given it is what
// tracing `ray` found, and the ray is not traced again.
template <TraversalBackend Accel>
Rgb estimateRadiance(const Accel& accel, const IntegratorContext& ctx, Ray ray, const PixelSample& sample,
                     RayCounters& rays, FirstHitAovs* firstHit = nullptr, const TracedRay* traced = nullptr) {
    const LightSet& lights = *ctx.lights;
    Rgb radiance(0.0f), throughput(1.0f);
    float etaScale = 1.0f;  // product of eta^2 over the refractions so far (see Russian roulette above)
    float previousBsdfPdf = 0.0f;
    bool previousWasDelta = true;  // the camera vertex: emitters seen directly get full weight
    Vec3f previousPosition = ray.origin;
    Vec3f previousNormal;  // its geometric normal: the light choice's probability there depends on it
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
        // --- Escape: the environment, weighted against its NEE.
        if (!found) {
            if (lights.hasEnvironment()) {
                const Rgb environment = lights.environmentRadiance(ray.direction);
                if (!environment.isBlack()) {
                    const float weight =
                        previousWasDelta
                            ? 1.0f
                            : detail::hitWeight(
                                  ctx.strategy, previousBsdfPdf,
                                  lights.pdfOfEnvironment(previousPosition, previousNormal, ray.direction));
                    radiance += throughput * environment * weight;
                }
            }
            break;
        }
        const SurfaceInteraction si = Accel::kReportsCanonicalHits || !ctx.canonicalHits
                                          ? resolveHit<true>(*ctx.scene, ray, hit, ctx.faceFrames)
                                          : resolveHit<false>(*ctx.scene, ray, hit, ctx.faceFrames);
        left = si.shape.kind == ShapeKind::Sphere ? TriangleLeft{} : TriangleLeft{hit.geomId, hit.primId};
        // Bounce rays leave in unit directions (the BSDF's, turned into the world); only the
        // caller's camera ray may not be.
        const Vec3f wo = bounce == 0 ? -normalize(ray.direction) : -ray.direction;
        const Material* shaded = &ctx.scene->materials[si.material];
        if (shaded->isTextured()) [[unlikely]]
            shaded = &textured.fill(detail::texturedMaterial(*shaded, ctx, si, ray.time));
        const Material& material = *shaded;
        const bool woAbove = dot(wo, si.geometricNormal) > 0.0f;
        if (bounce == 0 && firstHit)
            *firstHit = {true, hit.t * length(ray.direction), si.shadingNormal, material.albedo()};

        // --- Absorption: Beer-Lambert along the segment that arrived at the back side.
        if (!woAbove) {
            const Rgb sigma = material.interiorAbsorption();
            if (!sigma.isBlack()) {
                const float distance = hit.t * length(ray.direction);
                throughput *= Rgb(std::exp(-sigma.r * distance), std::exp(-sigma.g * distance),
                                  std::exp(-sigma.b * distance));
            }
        }

        // --- Emission at the hit, found by the previous vertex's BSDF sample: weighted against NEE.
        const Rgb emitted = lights.emitted(si, wo);
        if (!emitted.isBlack()) {
            const float weight =
                previousWasDelta ? 1.0f
                                 : detail::hitWeight(ctx.strategy, previousBsdfPdf,
                                                     lights.pdfOfHit(previousPosition, previousNormal, si));
            radiance += throughput * emitted * weight;
        }
        if (int(bounce) >= ctx.maxDepth) break;

        const Frame frame = si.shadingFrame ? *si.shadingFrame : Frame::fromNormal(si.shadingNormal);
        // How far the vertex's shadow and bounce rays start off the surface (either side).
        const float leaveDistance = offsetDistance(si.position, si.positionError, si.geometricNormal);
        const FrameLanes lanes(frame);
        const Vec3f woLocal = lanes.toLocal(wo);

        // --- Direct light (next-event estimation): the shadow ray and what it adds when
        // unoccluded. It is traced after the continuation's BSDF sample, not before: the two are
        // independent (bench/README.md, "Speed tricks").
        bool castsShadowRay = false;
        Ray shadowRay;
        Rgb shadowContribution;
        if (!lights.empty() && !material.isPurelySpecular() && ctx.strategy != LightStrategy::Bsdf) {
            // Sample values that would not be used are not drawn (each dimension is keyed on its
            // own, so skipping one leaves the others as they are). One 2D value chooses the light
            // and then the point on it (LightSet::choose); frozen, it fixes the point on each light
            // but not the choice (README, `--freeze`).
            Vec2f uLight{0.5f, 0.5f};
            LightSet::Choice light{0, 1.0f};
            if (lights.drawsSampleValues()) {
                uLight = sample.get2DUnfrozen(Dim::LightPosition, bounce);
                light = lights.choose(uLight, si.position, si.geometricNormal);
                if (sample.isFrozen(Dim::LightPosition)) [[unlikely]]
                    uLight = {0.5f, 0.5f};
            }
            const auto ls = lights.sample(light, si.position, uLight);
            const Vec3f wiLocal = ls ? lanes.toLocal(ls->direction) : Vec3f{};
            // Reflection needs the light on wo's side of the geometric surface, transmission on the other.
            const bool reflects = woLocal.z * wiLocal.z > 0.0f;
            const float cosLight = ls ? dot(ls->direction, si.geometricNormal) : 0.0f;
            if (ls && !ls->radiance.isBlack() && ((cosLight > 0.0f) == woAbove) == reflects) {
                const Rgb f = material.eval(woLocal, wiLocal, woAbove) * std::abs(wiLocal.z);
                if (!f.isBlack()) {
                    PENUMBRA_CHECK(ls->pdf > 0.0f, "a light sample has a positive density");
                    castsShadowRay = true;
                    shadowRay = detail::spawnShadowRay(si, leaveDistance, *ls, cosLight, ray.time);
                    const float weight =
                        ls->isDelta || ctx.strategy == LightStrategy::Light
                            ? 1.0f
                            : powerHeuristic(ls->pdf, material.pdf(woLocal, wiLocal, woAbove));
                    shadowContribution = throughput * f * ls->radiance * (weight / ls->pdf);
                }
            }
        }

        // --- Continuation: a BSDF sample for the next segment, then Russian roulette. Whether the
        // path goes on, and if so its next segment in `ray` (and its new throughput: the shadow
        // ray's contribution has the old one).
        const bool continues = [&]() __attribute__((always_inline)) {
            const float uLobe = material.usesLobeSample() ? sample.get1D(Dim::BsdfLobe, bounce) : 0.5f;
            const auto bs = material.sample(woLocal, uLobe, uDirection, woAbove);
            if (!bs) return false;
            PENUMBRA_CHECK(bs->pdf > 0.0f, "a BSDF sample has a positive density");
            const Vec3f wi = lanes.toWorld(bs->wi);
            PENUMBRA_CHECK(detail::isUnit(wi), "a BSDF sample's direction has unit length");
            const float cosWi = dot(wi, si.geometricNormal);
            // A reflection that crosses the geometric surface, or a transmission that does not.
            if (((cosWi > 0.0f) != woAbove) != bs->isTransmission()) return false;
            throughput *= bs->weight;
            if (bs->isTransmission()) etaScale *= bs->eta * bs->eta;
            if (throughput.isBlack()) return false;
            previousBsdfPdf = bs->pdf;
            previousWasDelta = bs->isSpecular();
            previousPosition = si.position;
            previousNormal = si.geometricNormal;

            if (int(bounce) + 1 >= ctx.rouletteStartDepth) {
                // A path that survives for certain draws no sample (u < 1 never ends it).
                const float survival = std::min(1.0f, std::sqrt((throughput * etaScale).maxComponent()));
                if (survival < 1.0f) {
                    if (sample.get1D(Dim::RussianRoulette, bounce) >= survival) return false;
                    throughput *= 1.0f / survival;
                }
            }
            PENUMBRA_CHECK(throughput.isFinite() && throughput.minComponent() >= 0.0f,
                           "a path's throughput is finite and non-negative");
            // The ray past the last vertex only looks for emission; without emitters it could hit,
            // it is not traced (as Embree's pathtracer counts path length).
            if (int(bounce) + 1 >= ctx.maxDepth && !lights.emitsAlongRays()) return false;
            detail::continueRay(ray, si, leaveDistance, wi, cosWi);
            return true;
        }
        ();

        // --- The pending shadow ray.
        if (castsShadowRay) {
            ++rays.shadow;
            if (!accel.occluded(shadowRay, left)) radiance += shadowContribution;
        }
        if (!continues) break;
        ++rays.extension;
    }
    return radiance;
}

}  // namespace penumbra
