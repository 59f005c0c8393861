#include "lights/light_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/frame.h"
#include "core/sampling.h"

namespace penumbra {

namespace {

// Radius of a sphere that bounds all geometry, for the environment's power estimate.
float sceneBoundingRadius(const SceneGeometry& scene) {
    Vec3f lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
             std::numeric_limits<float>::max()};
    Vec3f hi = -lo;
    bool any = false;
    for (const auto& mesh : scene.meshes)
        for (const Vec3f& p : mesh.positions) {
            lo = min(lo, p);
            hi = max(hi, p);
            any = true;
        }
    for (const auto& s : scene.spheres) {
        lo = min(lo, s.center - Vec3f(s.radius, s.radius, s.radius));
        hi = max(hi, s.center + Vec3f(s.radius, s.radius, s.radius));
        any = true;
    }
    for (const Curves& curves : scene.curves)
        for (const Vec3f& p : curves.points) {
            lo = min(lo, p);
            hi = max(hi, p);
            any = true;
        }
    return any ? std::max(0.5f * length(hi - lo), 1e-3f) : 1.0f;
}

// The bounds of an emitting mesh's triangles together: a sphere about their box, and the cone
// about their area-weighted mean normal that holds every triangle's normal.
LightBounds meshBounds(const LightModel* lights, uint32_t count, float power) {
    const auto triangle = [lights](uint32_t i) -> const TriangleLight& {
        return std::get<TriangleLight>(lights[i]);
    };
    Vec3f lo = triangle(0).p0, hi = triangle(0).p0, normalSum;
    for (uint32_t i = 0; i < count; ++i) {
        const TriangleLight& t = triangle(i);
        lo = min(lo, min(t.p0, min(t.p1, t.p2)));
        hi = max(hi, max(t.p0, max(t.p1, t.p2)));
        normalSum += t.normal * t.area;
    }
    LightBounds b;
    b.phi = power;
    b.center = (lo + hi) * 0.5f;
    float radiusSquared = 0.0f;
    for (uint32_t i = 0; i < count; ++i)
        for (const Vec3f& p : {triangle(i).p0, triangle(i).p1, triangle(i).p2})
            radiusSquared = std::max(radiusSquared, lengthSquared(p - b.center));
    // Widened by a little more than rounding, so that no vertex lies outside.
    b.radius = std::sqrt(radiusSquared) * 1.0001f;
    b.twoSided = triangle(0).twoSided;
    const float sumLength = length(normalSum);
    if (!(sumLength > 0.0f)) return b;  // normals cancel: every direction (cosThetaO = -1)
    b.axis = normalSum / sumLength;
    float cosSpread = 1.0f;
    for (uint32_t i = 0; i < count; ++i)
        if (triangle(i).area > 0.0f) cosSpread = std::min(cosSpread, dot(b.axis, triangle(i).normal));
    b.cosThetaO = std::clamp(cosSpread - 1e-5f, -1.0f, 1.0f);
    return b;
}

}  // namespace

LightSet::LightSet(const SceneGeometry& scene, const std::vector<LightModel>& sceneLights,
                   const EnvironmentLight& environment, LightSampler sampler)
    : hasEnvironment_(!environment.isBlack()),
      environment_(std::make_shared<const EnvironmentLight>(environment)) {
    std::vector<uint32_t> emitterSizes;  // lights per emitter, in order: a mesh's triangles, or one light
    meshFirstLight_.assign(scene.meshes.size(), -1);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (!mesh.emission.emits()) continue;
        meshFirstLight_[m] = int32_t(lights_.size());
        for (size_t t = 0; t < mesh.triangleCount(); ++t) lights_.push_back(TriangleLight::fromMesh(mesh, t));
        if (mesh.triangleCount() > 0) emitterSizes.push_back(uint32_t(mesh.triangleCount()));
    }
    sphereLight_.assign(scene.spheres.size(), -1);
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        if (!scene.spheres[s].emission.emits()) continue;
        sphereLight_[s] = int32_t(lights_.size());
        lights_.push_back(SphereLight::fromSphere(scene.spheres[s]));
        emitterSizes.push_back(1);
    }
    hasAreaLights_ = !lights_.empty();
    // The scene's lights grouped by model, in the variant's order (finite before infinite), each
    // model's in the scene's order.
    std::vector<LightModel> named = sceneLights;
    std::stable_sort(named.begin(), named.end(),
                     [](const LightModel& a, const LightModel& b) { return a.index() < b.index(); });
    for (LightModel& light : named) {
        PENUMBRA_CHECK(!std::holds_alternative<TriangleLight>(light) &&
                           !std::holds_alternative<SphereLight>(light) &&
                           !std::holds_alternative<EnvironmentEmitter>(light),
                       "area lights and the environment come from the scene's shapes and environment");
        lights_.push_back(std::move(light));
        emitterSizes.push_back(1);
    }
    if (hasEnvironment_) {
        environmentLight_ = int32_t(lights_.size());
        lights_.push_back(EnvironmentEmitter{environment_});
        emitterSizes.push_back(1);
    }
    // Degenerate triangles get zero power and so are never chosen.
    const double sceneRadius = sceneBoundingRadius(scene);
    std::vector<double> power;
    power.reserve(lights_.size());
    for (const LightModel& light : lights_)
        power.push_back(std::visit([sceneRadius](const auto& l) { return l.power(sceneRadius); }, light));
    choice_ = DiscreteDistribution(power);
    drawsSampleValues_ = lights_.size() > 1 || (lights_.size() == 1 && !isDelta(0));
    for (const LightModel& light : lights_)
        hasPointIndependentLights_ =
            hasPointIndependentLights_ || penumbra::isPointIndependentOfReference(light);

    if (sampler == LightSampler::Bvh) groupEmitters(emitterSizes, power);
}

void LightSet::groupEmitters(std::vector<uint32_t> emitterSizes, const std::vector<double>& power) {
    // Choosing at a vertex pays where there are two emitters or more (a quad light alone gains
    // nothing by weighing its two triangles). Where all lights fit the batch, each is weighed on
    // its own: its bounds are tighter than its mesh's.
    size_t finiteEmitterCount = 0;
    for (uint32_t first = 0; const uint32_t size : emitterSizes) {
        finiteEmitterCount += isInfinite(first) ? 0 : 1;
        first += size;
    }
    if (finiteEmitterCount < 2) return;
    if (choice_.empty()) return;
    if (lights_.size() <= kMaxLocallyChosenEmitters) emitterSizes.assign(lights_.size(), 1);
    if (emitterSizes.size() > kMaxLocallyChosenEmitters) {
        buildTree(power);
        return;
    }
    emitterOfLight_.resize(lights_.size());
    probabilityWithinEmitter_.resize(lights_.size());
    for (uint32_t first = 0; const uint32_t size : emitterSizes) {
        Emitter emitter;
        emitter.firstLight = first;
        emitter.lightCount = size;
        emitter.infinite = isInfinite(first);
        std::vector<double> shares(power.begin() + first, power.begin() + first + size);
        emitter.withinEmitter = DiscreteDistribution(shares);
        for (uint32_t i = first; i < first + size; ++i) {
            emitter.powerShare += choice_.probability(i);
            emitterOfLight_[i] = uint32_t(emitters_.size());
            probabilityWithinEmitter_[i] =
                emitter.withinEmitter.empty() ? 0.0f : emitter.withinEmitter.probability(i - first);
            if (emitter.infinite) {
                hasInfiniteLights_ = true;
                finiteShare_ -= choice_.probability(i);
            }
        }
        emitters_.push_back(std::move(emitter));
        first += size;
    }
    finiteShare_ = std::max(finiteShare_, 0.0f);
    choosesLocally_ = true;
    for (size_t e = 0; e < emitters_.size(); ++e) {
        if (emitters_[e].infinite) {
            bounds_.set(e, LightBounds{});  // power 0: importance 0 (their weight is their power share)
            continue;
        }
        const uint32_t first = emitters_[e].firstLight, size = emitters_[e].lightCount;
        double emitterPower = 0.0;
        for (uint32_t i = first; i < first + size; ++i) emitterPower += power[i];
        bounds_.set(e, size == 1 ? std::visit([&](const auto& l) { return l.bounds(float(emitterPower)); },
                                              lights_[first])
                                 : meshBounds(&lights_[first], size, float(emitterPower)));
    }
}

void LightSet::buildTree(const std::vector<double>& power) {
    std::vector<LightBounds> bounds(lights_.size());  // infinite lights: power 0, left out of the tree
    for (uint32_t i = 0; i < lights_.size(); ++i) {
        if (isInfinite(i)) {
            infiniteLights_.push_back(i);
            finiteShare_ -= choice_.probability(i);
            continue;
        }
        bounds[i] = std::visit([&](const auto& l) { return l.bounds(float(power[i])); }, lights_[i]);
    }
    PENUMBRA_CHECK(
        infiniteLights_.empty() || infiniteLights_.back() - infiniteLights_[0] + 1 == infiniteLights_.size(),
        "the infinite lights come last (the constructor's order)");
    tree_ = LightTree(bounds);
    if (tree_.empty()) return;  // no finite light has power: by power, then
    std::vector<double> infinitePower;
    for (const uint32_t i : infiniteLights_) infinitePower.push_back(power[i]);
    infiniteChoice_ = DiscreteDistribution(infinitePower);
    hasInfiniteLights_ = !infiniteChoice_.empty();
    finiteShare_ = hasInfiniteLights_ ? std::clamp(finiteShare_, 0.0f, 1.0f) : 1.0f;
    choosesLocally_ = true;
}

LightSet::Choice LightSet::chooseByTree(Vec2f& uPoint, Vec3f p, Vec3f n) const {
    float& u = uPoint.x;
    if (hasInfiniteLights_) {
        if (u >= finiteShare_) {
            u = std::clamp((u - finiteShare_) / (1.0f - finiteShare_), 0.0f,
                           DiscreteDistribution::kOneMinusUlp);
            const uint32_t k = infiniteChoice_.sampleAndRemap(u);
            return {infiniteLights_[k], (1.0f - finiteShare_) * infiniteChoice_.probability(k)};
        }
        u = std::min(u / finiteShare_, DiscreteDistribution::kOneMinusUlp);
    }
    const LightTree::Choice choice = tree_.choose(u, p, n);
    return {choice.light, finiteShare_ * choice.probability};
}

float LightSet::localChoiceWeights(Vec3f p, Vec3f n, float* weights) const {
    // The infinite lights' slots hold empty bounds: their importance is 0.
    bounds_.importances(p, n, weights);
    float finiteTotal = 0.0f;
    for (size_t e = 0; e < emitters_.size(); ++e) finiteTotal += weights[e];
    if (!(finiteTotal > 0.0f)) {
        // No finite light can light the point: any choice among them adds nothing; by power, then.
        for (size_t e = 0; e < emitters_.size(); ++e) weights[e] = emitters_[e].powerShare;
        return 1.0f;
    }
    if (!hasInfiniteLights_) return finiteTotal;
    // The infinite lights' power shares, scaled to the finite lights' importances.
    const float scale = finiteTotal / finiteShare_;
    float total = finiteTotal;
    for (size_t e = 0; e < emitters_.size(); ++e)
        if (emitters_[e].infinite) {
            weights[e] = emitters_[e].powerShare * scale;
            total += weights[e];
        }
    return total;
}

LightSet::Choice LightSet::chooseLocally(Vec2f& uPoint, Vec3f p, Vec3f n) const {
    if (!tree_.empty()) return chooseByTree(uPoint, p, n);
    float weights[kMaxLocallyChosenEmitters];
    const float total = localChoiceWeights(p, n, weights);
    // The emitter whose interval of [0, total) holds uPoint.x * total; uPoint.x then becomes the
    // position within it (DiscreteDistribution::sampleAndRemap), which chooses among its lights.
    const float target = uPoint.x * total;
    size_t chosen = emitters_.size();
    float chosenStart = 0.0f, start = 0.0f;
    for (size_t e = 0; e < emitters_.size(); ++e) {
        if (weights[e] > 0.0f) {  // an emitter of weight 0 is never chosen, even through rounding
            chosen = e;
            chosenStart = start;
            if (target < start + weights[e]) break;
        }
        start += weights[e];
    }
    PENUMBRA_CHECK(chosen < emitters_.size(), "some emitter has a positive weight");
    if (chosen >= emitters_.size()) chosen = 0;
    const float weight = weights[chosen];
    uPoint.x = std::clamp((target - chosenStart) / weight, 0.0f, DiscreteDistribution::kOneMinusUlp);
    const Emitter& emitter = emitters_[chosen];
    const uint32_t light = emitter.firstLight + emitter.withinEmitter.sampleAndRemap(uPoint.x);
    return {light, weight / total * probabilityWithinEmitter_[light]};
}

float LightSet::localChoiceProbability(uint32_t light, Vec3f p, Vec3f n) const {
    if (!tree_.empty()) {
        if (!isInfinite(light)) return finiteShare_ * tree_.probability(light, p, n);
        return hasInfiniteLights_
                   ? (1.0f - finiteShare_) * infiniteChoice_.probability(light - infiniteLights_[0])
                   : 0.0f;
    }
    float weights[kMaxLocallyChosenEmitters];
    const float total = localChoiceWeights(p, n, weights);
    return weights[emitterOfLight_[light]] / total * probabilityWithinEmitter_[light];
}

std::optional<LightSample> LightSet::sampleOther(Choice choice, Vec3f reference, Vec2f u) const {
    // Built in place in the result, which is returned by name: a LightSample built aside went to
    // the result through vector registers and the stack, in pieces the loads that followed could
    // not be forwarded from (bench/README.md, "Speed tricks").
    std::optional<LightSample> result(std::in_place);
    if (!sampleOtherInto(choice, reference, u, *result)) result.reset();
    return result;
}

bool LightSet::sampleOtherInto(Choice choice, Vec3f reference, Vec2f u, LightSample& ls) const {
    if (!std::visit([&](const auto& light) { return light.sample(reference, u, ls); }, lights_[choice.light]))
        return false;
    ls.pdf = choice.probability * ls.pdf;
    return ls.pdf > 0.0f && std::isfinite(ls.pdf);
}

int32_t LightSet::lightIndexOf(ShapeRef shape) const {
    switch (shape.kind) {
        case ShapeKind::Mesh: {
            const int32_t first = meshFirstLight_[shape.index];
            return first < 0 ? -1 : first + int32_t(shape.primitive);
        }
        case ShapeKind::Sphere:
            return sphereLight_[shape.index];
        case ShapeKind::Instance:
        case ShapeKind::Curves:
        case ShapeKind::BilinearPatches:
            return -1;  // instances, curves and bilinear patches never emit (the scene loader refuses it)
    }
    return -1;
}

Rgb LightSet::emittedByAreaLight(const SurfaceInteraction& si, Vec3f towardsViewer) const {
    const int32_t index = lightIndexOf(si.shape);
    if (index < 0) return Rgb(0.0f);
    return std::visit(
        [&](const auto& light) {
            if constexpr (requires { light.emitted(si, towardsViewer); })
                return light.emitted(si, towardsViewer);
            else
                return Rgb(0.0f);  // lightIndexOf names area lights only
        },
        lights_[index]);
}

float LightSet::pdfOfHit(Vec3f reference, Vec3f referenceNormal, const SurfaceInteraction& si) const {
    const int32_t index = lightIndexOf(si.shape);
    if (index < 0) return 0.0f;
    return choiceProbability(uint32_t(index), reference, referenceNormal) *
           std::visit([&](const auto& light) { return light.pdf(reference, si.position); }, lights_[index]);
}

float LightSet::pdfOfHitChosenAt(Vec3f choiceReference, Vec3f reference, const SurfaceInteraction& si) const {
    const int32_t index = lightIndexOf(si.shape);
    if (index < 0 || !isPointIndependentOfReference(uint32_t(index))) return 0.0f;
    return choiceProbability(uint32_t(index), choiceReference, Vec3f{}) *
           std::visit([&](const auto& light) { return light.pdf(reference, si.position); }, lights_[index]);
}

float LightSet::pdfOfEnvironment(Vec3f reference, Vec3f referenceNormal, Vec3f direction) const {
    if (environmentLight_ < 0) return 0.0f;
    return choiceProbability(uint32_t(environmentLight_), reference, referenceNormal) *
           environment_->pdf(direction);
}

}  // namespace penumbra
