// The lights of a scene as one closed set: emitting triangles, emitting spheres, point, spot and
// directional lights and the environment (lights/environment_light.h). Next-event estimation picks
// one light with probability proportional to its power, then a point on it (triangles by area,
// spheres by the solid angle they subtend) or a direction (the environment: uniformly for a
// constant one, by luminance for an image).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/discrete_distribution.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "geometry/scene_geometry.h"
#include "geometry/surface_interaction.h"
#include "lights/environment_light.h"
#include "lights/light.h"

namespace penumbra {

enum class LightKind : uint8_t { Triangle, Sphere, Point, Spot, Directional, Environment };

struct Light {
    LightKind kind = LightKind::Point;
    Rgb radiance;            // area lights: radiance; point, spot: intensity; directional: irradiance
    bool twoSided = false;   // area lights
    Vec3f p0, p1, p2;        // triangle vertices
    Vec3f normal;            // triangle front normal (unit); directional: the direction light travels; spot: its axis
    float area = 0;          // triangle area
    float cosFalloffStart = 1, cosFalloffEnd = 1;  // spot lights (lights/light.h)
    Vec3f center;            // sphere centre or point- or spot-light position
    float radius = 0;        // sphere radius
    const Texture* texture = nullptr;  // textured emission (geometry/emission.h); radiance then its average
    Vec2f uv0, uv1, uv2;     // textured triangles: the vertices' uvs
};

struct LightSample {
    Vec3f direction;   // unit, from the reference point towards the light
    float distance;    // to the sampled point; infinity for the environment
    Vec3f point;       // sampled point on the light (for area lights)
    Vec3f pointError;  // bound on each coordinate's absolute error of point (core/ray_offset.h)
    Vec3f lightNormal; // front normal at the sampled point (area lights)
    Rgb radiance;      // arriving along -direction (intensity / distance^2 for point lights)
    float pdf;         // solid-angle density including the light choice; choice probability for deltas
    bool isDelta;
};

class LightSet {
public:
    LightSet() = default;
    LightSet(const SceneGeometry& geometry, const std::vector<PointLight>& pointLights,
             const std::vector<SpotLight>& spotLights, const std::vector<DirectionalLight>& directionalLights,
             const EnvironmentLight& environment);

    bool empty() const { return choice_.empty(); }
    // Whether a ray can find emission by hitting something (an area light or the environment);
    // with only point and directional lights it cannot.
    bool emitsAlongRays() const { return hasAreaLights_ || !environment_.isBlack(); }
    size_t size() const { return lights_.size(); }

    // Next-event estimation in two steps: choose() picks a light by power with uPoint.x and leaves
    // in uPoint.x its position within the light's share, then sample() takes a point on the light
    // with uPoint (one 2D sample for both, so each light's points stay stratified). Point, spot and
    // directional lights (isDelta) ignore uPoint; with a single light choose() leaves it as it is.
    uint32_t choose(Vec2f& uPoint) const { return choice_.sampleAndRemap(uPoint.x); }
    // Whether next-event estimation uses sample values at all: not for one delta light.
    bool drawsSampleValues() const { return drawsSampleValues_; }
    bool isDelta(uint32_t light) const {
        const LightKind kind = lights_[light].kind;
        return kind == LightKind::Point || kind == LightKind::Spot || kind == LightKind::Directional;
    }
    std::optional<LightSample> sample(uint32_t light, Vec3f reference, Vec2f uPoint) const {
        // Point lights, the common case, inline; the other kinds in lights.cpp.
        if (lights_[light].kind == LightKind::Point) return samplePoint(light, reference);
        return sampleOther(light, reference, uPoint);
    }

    // Emitted radiance leaving a surface point towards `towardsViewer` (0 for non-emitters).
    Rgb emitted(const SurfaceInteraction& si, Vec3f towardsViewer) const {
        return hasAreaLights_ ? emittedByAreaLight(si, towardsViewer) : Rgb(0.0f);
    }
    bool hasEnvironment() const { return !environment_.isBlack(); }
    // Radiance arriving along -direction from the environment, for a ray that escapes.
    Rgb environmentRadiance(Vec3f direction) const { return environment_.radiance(direction); }

    // Density with which sample() from `reference` would have produced the emitter point `si`
    // (solid angle, light choice included): the MIS weight of a BSDF-sampled hit.
    float pdfOfHit(Vec3f reference, const SurfaceInteraction& si) const;
    // The same for a ray that escaped along `direction` (the ray's own: it need not be unit).
    float pdfOfEnvironment(Vec3f direction) const;

private:
    std::optional<LightSample> samplePoint(uint32_t index, Vec3f reference) const {
        const Light& light = lights_[index];
        const Vec3f toLight = light.center - reference;
        const float distanceSquared = lengthSquared(toLight);
        if (!(distanceSquared > 0.0f)) return std::nullopt;
        LightSample ls{};
        ls.distance = std::sqrt(distanceSquared);
        ls.direction = toLight / ls.distance;
        ls.point = light.center;
        ls.radiance = light.radiance / distanceSquared;
        ls.pdf = choice_.probability(index);
        ls.isDelta = true;
        return ls;
    }
    std::optional<LightSample> sampleOther(uint32_t index, Vec3f reference, Vec2f uPoint) const;
    Rgb emittedByAreaLight(const SurfaceInteraction& si, Vec3f towardsViewer) const;
    int32_t lightIndexOf(ShapeRef shape) const;
    float solidAnglePdf(const Light& light, Vec3f reference, Vec3f point) const;
    // A density of 1 / area over a surface, per solid angle at a point `distanceSquared` away
    // whose direction makes the cosine `cosAtLight` (>= 0) with the surface; 0 where none is.
    static float areaToSolidAnglePdf(float distanceSquared, float cosAtLight, float area) {
        return (area > 0.0f && cosAtLight > 0.0f) ? distanceSquared / (cosAtLight * area) : 0.0f;
    }

    std::vector<Light> lights_;
    DiscreteDistribution choice_;
    std::vector<int32_t> meshFirstLight_;    // per mesh: index of its first triangle light, or -1
    std::vector<int32_t> sphereLight_;       // per sphere: its light index, or -1
    int32_t environmentLight_ = -1;
    bool hasAreaLights_ = false;
    bool drawsSampleValues_ = false;  // more than one light, or one that is not a delta light
    EnvironmentLight environment_;
};

}  // namespace penumbra
