// The lights of a scene as one closed set (lights/light.h: emitting triangles and spheres, point,
// spot and directional lights and the environment), and the choice among them. Next-event estimation picks
// one light, by what it can contribute at the vertex or by power (choose()), then a point on it
// (triangles by area, spheres by the solid angle they subtend) or a direction (the environment:
// uniformly for a constant one, by luminance for an image).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "core/discrete_distribution.h"
#include "core/rgb.h"
#include "core/vec.h"
#include "geometry/scene_geometry.h"
#include "geometry/surface_interaction.h"
#include "lights/environment_light.h"
#include "lights/light.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"
#include "lights/light_sampler.h"
#include "lights/light_tree.h"

namespace penumbra {

class LightSet {
public:
    LightSet() = default;
    // The area lights of `geometry`'s emitting shapes, the lights the scene names (`sceneLights`:
    // none of them an area light or an environment) and `environment`.
    LightSet(const SceneGeometry& geometry, const std::vector<LightModel>& sceneLights,
             const EnvironmentLight& environment, LightSampler sampler = LightSampler::Bvh);

    bool empty() const { return choice_.empty(); }
    // Whether a ray can find emission by hitting something (an area light or the environment);
    // with only point and directional lights it cannot.
    bool emitsAlongRays() const { return hasAreaLights_ || hasEnvironment_; }
    size_t size() const { return lights_.size(); }

    // Next-event estimation in two steps: choose() picks a light for the vertex at `p` (surface
    // normal `n`) with uPoint.x and leaves in uPoint.x its position within the light's share, then
    // sample() takes a point on the light with uPoint (one 2D sample for both, so each light's
    // points stay stratified). Point, spot and directional lights (isDelta) ignore uPoint; with a
    // single light choose() leaves it as it is.
    //
    // The choice (LightSampler::Bvh): where the scene has two finite emitters or more (an emitter
    // is one light, or an emitting mesh's triangles together) and at most
    // kMaxLocallyChosenEmitters emitters in all, an emitter by what it can contribute at the
    // vertex (lights/light_bounds.h, as pbrt-v4's light BVH weighs its nodes), the infinite lights
    // (directional, environment) keeping their share of the power, then one of its lights by
    // power; where all lights fit, each light is an emitter of its own. With more emitters, the
    // infinite lights by their power share, the finite ones by a tree over each of their lights
    // (lights/light_tree.h). With one finite emitter, or LightSampler::Power, by power alone.
    struct Choice {
        uint32_t light;
        float probability;
    };
    static constexpr size_t kMaxLocallyChosenEmitters = LightBoundsBatch::kCapacity;
    Choice choose(Vec2f& uPoint, Vec3f p, Vec3f n) const {
        if (!choosesLocally_) {
            const uint32_t light = choice_.sampleAndRemap(uPoint.x);
            return {light, choice_.probability(light)};
        }
        return chooseLocally(uPoint, p, n);
    }
    // The probability that choose() at (p, n) picks `light`.
    float choiceProbability(uint32_t light, Vec3f p, Vec3f n) const {
        return choosesLocally_ ? localChoiceProbability(light, p, n) : choice_.probability(light);
    }
    // Whether the choice depends on the vertex (see choose()).
    bool choosesLocally() const { return choosesLocally_; }
    // Whether next-event estimation uses sample values at all: not for one delta light.
    bool drawsSampleValues() const { return drawsSampleValues_; }
    bool isDelta(uint32_t light) const { return isDeltaLight(lights_[light]); }
    bool isPointIndependentOfReference(uint32_t light) const {
        return penumbra::isPointIndependentOfReference(lights_[light]);
    }
    // Whether any light is (LightModelType's kPointIndependentOfReference).
    bool hasPointIndependentLights() const { return hasPointIndependentLights_; }
    const LightModel& light(uint32_t light) const { return lights_[light]; }
    // A point on the light `choice` names, seen from `reference`; its pdf includes the choice's
    // probability. Point lights, the common case, inline; the others out of line, built in place
    // (bench/README.md, "Speed tricks", `LightSet::sampleOther`).
    std::optional<LightSample> sample(Choice choice, Vec3f reference, Vec2f uPoint) const {
        if (const auto* point = std::get_if<PointLight>(&lights_[choice.light])) {
            LightSample ls{};
            if (!samplePointSource(point->position, point->intensity, reference, ls)) return std::nullopt;
            ls.pdf = choice.probability;  // times the point light's own density, 1
            return ls;
        }
        return sampleOther(choice, reference, uPoint);
    }

    // Emitted radiance leaving a surface point towards `towardsViewer` (0 for non-emitters).
    Rgb emitted(const SurfaceInteraction& si, Vec3f towardsViewer) const {
        return hasAreaLights_ ? emittedByAreaLight(si, towardsViewer) : Rgb(0.0f);
    }
    bool hasEnvironment() const { return hasEnvironment_; }
    // Radiance arriving along -direction from the environment, for a ray that escapes.
    Rgb environmentRadiance(Vec3f direction) const { return environment_->radiance(direction); }

    // Density with which choose() and sample() from `reference` (surface normal `referenceNormal`)
    // would have produced the emitter point `si` (solid angle, light choice included): the MIS
    // weight of a BSDF-sampled hit.
    float pdfOfHit(Vec3f reference, Vec3f referenceNormal, const SurfaceInteraction& si) const;
    // The same for a ray that escaped along `direction` (the ray's own: it need not be unit).
    float pdfOfEnvironment(Vec3f reference, Vec3f referenceNormal, Vec3f direction) const;
    // The density, per solid angle at `reference`, of next-event estimation sampling the hit `si`
    // with the light chosen at the medium point `choiceReference` instead (equiangular sampling
    // chooses before it knows the point it lights); 0 for lights whose points depend on the
    // reference (isPointIndependentOfReference).
    float pdfOfHitChosenAt(Vec3f choiceReference, Vec3f reference, const SurfaceInteraction& si) const;

private:
    std::optional<LightSample> sampleOther(Choice choice, Vec3f reference, Vec2f uPoint) const;
    // sampleOther's work, written into `ls` (false: no sample).
    bool sampleOtherInto(Choice choice, Vec3f reference, Vec2f uPoint, LightSample& ls) const;
    bool isInfinite(size_t light) const { return isInfiniteLight(lights_[light]); }
    // An emitter: lights_[firstLight, firstLight + lightCount), chosen among by power.
    struct Emitter {
        uint32_t firstLight = 0, lightCount = 0;
        bool infinite = false;
        float powerShare = 0.0f;  // its lights' probabilities under the choice by power, summed
        DiscreteDistribution withinEmitter;
    };
    void groupEmitters(std::vector<uint32_t> emitterSizes, const std::vector<double>& power);
    // The choice's weights at (p, n), one per emitter, into `weights` (room for
    // kMaxLocallyChosenEmitters): the finite emitters' importances, and the infinite lights' power
    // shares scaled so that they keep that share of the sum. Returns the sum; choose() and
    // choiceProbability() divide by it alike.
    float localChoiceWeights(Vec3f p, Vec3f n, float* weights) const;
    Choice chooseLocally(Vec2f& uPoint, Vec3f p, Vec3f n) const;
    void buildTree(const std::vector<double>& power);
    Choice chooseByTree(Vec2f& uPoint, Vec3f p, Vec3f n) const;
    float localChoiceProbability(uint32_t light, Vec3f p, Vec3f n) const;
    Rgb emittedByAreaLight(const SurfaceInteraction& si, Vec3f towardsViewer) const;
    int32_t lightIndexOf(ShapeRef shape) const;

    std::vector<LightModel> lights_;
    DiscreteDistribution choice_;  // by power
    // The choice at a vertex (choosesLocally_): emitters, their bounds (finite ones), and each
    // light's emitter and probability within it.
    std::vector<Emitter> emitters_;
    LightBoundsBatch bounds_;
    std::vector<uint32_t> emitterOfLight_;
    std::vector<float> probabilityWithinEmitter_;
    // The choice among many lights: the finite ones by the tree, the infinite ones by power.
    LightTree tree_;
    std::vector<uint32_t> infiniteLights_;
    DiscreteDistribution infiniteChoice_;
    bool choosesLocally_ = false;
    float finiteShare_ = 1.0f;             // the finite lights' share of the power
    bool hasInfiniteLights_ = false;       // directional or environment
    std::vector<int32_t> meshFirstLight_;  // per mesh: index of its first triangle light, or -1
    std::vector<int32_t> sphereLight_;     // per sphere: its light index, or -1
    int32_t environmentLight_ = -1;
    bool hasAreaLights_ = false;
    bool hasEnvironment_ = false;
    bool drawsSampleValues_ = false;
    bool hasPointIndependentLights_ = false;  // more than one light, or one that is not a delta light
    std::shared_ptr<const EnvironmentLight> environment_;  // black where the scene has none
};

}  // namespace penumbra
