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
    return any ? std::max(0.5f * length(hi - lo), 1e-3f) : 1.0f;
}

// A sphere's (u, v) at its outward normal, as geometry/surface_interaction.h computes it.
Vec2f sphereUv(Vec3f outward) {
    const float phi = std::atan2(outward.y, outward.x);
    return {phi < 0.0f ? phi / (2.0f * kPi) + 1.0f : phi / (2.0f * kPi),
            std::acos(std::clamp(outward.z, -1.0f, 1.0f)) / kPi};
}

// Textured emission is looked up without a footprint (the finest level).
Rgb emittedRadiance(const Texture& texture, Vec2f uv) {
    TextureQuery query;
    query.uv = uv;
    return texture.evaluate(query);
}

// The bounds by which a finite light is chosen at a vertex (lights/light_bounds.h).
LightBounds lightBounds(const Light& light, float power) {
    LightBounds b;
    b.phi = power;
    switch (light.kind) {
        case LightKind::Triangle: {
            b.center = (light.p0 + light.p1 + light.p2) / 3.0f;
            b.radius =
                std::sqrt(std::max({lengthSquared(light.p0 - b.center), lengthSquared(light.p1 - b.center),
                                    lengthSquared(light.p2 - b.center)}));
            b.axis = light.normal;
            b.cosThetaO = 1.0f;  // one normal
            b.twoSided = light.twoSided;
            break;
        }
        case LightKind::Sphere:
            b.center = light.center;
            b.radius = light.radius;
            break;
        case LightKind::Point:
            b.center = light.center;
            break;
        case LightKind::Spot:
            // The falloff's start bounds the full intensity; beyond it, to the cone's end, the
            // emission angle.
            b.center = light.center;
            b.axis = light.normal;
            b.cosThetaO = light.cosFalloffStart;
            b.cosThetaE = std::cos(std::acos(std::clamp(light.cosFalloffEnd, -1.0f, 1.0f)) -
                                   std::acos(std::clamp(light.cosFalloffStart, -1.0f, 1.0f)));
            break;
        case LightKind::Directional:
        case LightKind::Environment:
            break;  // infinite: chosen by their power share
    }
    return b;
}

// The bounds of an emitting mesh's triangles together: a sphere about their box, and the cone
// about their area-weighted mean normal that holds every triangle's normal.
LightBounds meshBounds(const Light* triangles, uint32_t count, float power) {
    Vec3f lo = triangles[0].p0, hi = triangles[0].p0, normalSum;
    for (uint32_t i = 0; i < count; ++i) {
        const Light& t = triangles[i];
        lo = min(lo, min(t.p0, min(t.p1, t.p2)));
        hi = max(hi, max(t.p0, max(t.p1, t.p2)));
        normalSum += t.normal * t.area;
    }
    LightBounds b;
    b.phi = power;
    b.center = (lo + hi) * 0.5f;
    float radiusSquared = 0.0f;
    for (uint32_t i = 0; i < count; ++i)
        for (const Vec3f& p : {triangles[i].p0, triangles[i].p1, triangles[i].p2})
            radiusSquared = std::max(radiusSquared, lengthSquared(p - b.center));
    // Widened by a little more than rounding, so that no vertex lies outside.
    b.radius = std::sqrt(radiusSquared) * 1.0001f;
    b.twoSided = triangles[0].twoSided;
    const float sumLength = length(normalSum);
    if (!(sumLength > 0.0f)) return b;  // normals cancel: every direction (cosThetaO = -1)
    b.axis = normalSum / sumLength;
    float cosSpread = 1.0f;
    for (uint32_t i = 0; i < count; ++i)
        if (triangles[i].area > 0.0f) cosSpread = std::min(cosSpread, dot(b.axis, triangles[i].normal));
    b.cosThetaO = std::clamp(cosSpread - 1e-5f, -1.0f, 1.0f);
    return b;
}

}  // namespace

LightSet::LightSet(const SceneGeometry& scene, const std::vector<PointLight>& pointLights,
                   const std::vector<SpotLight>& spotLights,
                   const std::vector<DirectionalLight>& directionalLights,
                   const EnvironmentLight& environment)
    : environment_(environment) {
    std::vector<double> power;
    std::vector<uint32_t> emitterSizes;  // lights per emitter, in order: a mesh's triangles, or one light
    meshFirstLight_.assign(scene.meshes.size(), -1);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        if (!mesh.emission.emits()) continue;
        meshFirstLight_[m] = int32_t(lights_.size());
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            Light light;
            light.kind = LightKind::Triangle;
            light.radiance = mesh.emission.radiance;
            light.twoSided = mesh.emission.twoSided;
            light.p0 = mesh.positions[mesh.indices[3 * t]];
            light.p1 = mesh.positions[mesh.indices[3 * t + 1]];
            light.p2 = mesh.positions[mesh.indices[3 * t + 2]];
            light.texture = mesh.emission.texture.get();
            if (light.texture && !mesh.uvs.empty()) {
                light.uv0 = mesh.uvs[mesh.indices[3 * t]];
                light.uv1 = mesh.uvs[mesh.indices[3 * t + 1]];
                light.uv2 = mesh.uvs[mesh.indices[3 * t + 2]];
            }
            const Vec3f n = cross(light.p1 - light.p0, light.p2 - light.p0);
            light.area = 0.5f * length(n);
            light.normal = light.area > 0.0f ? normalize(n) : Vec3f{0, 0, 1};
            lights_.push_back(light);
            // Degenerate triangles get zero power and so are never chosen.
            power.push_back(double(light.radiance.luminance()) * light.area * kPi * (light.twoSided ? 2 : 1));
        }
        if (mesh.triangleCount() > 0) emitterSizes.push_back(uint32_t(mesh.triangleCount()));
    }
    sphereLight_.assign(scene.spheres.size(), -1);
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        const Sphere& sphere = scene.spheres[s];
        if (!sphere.emission.emits()) continue;
        sphereLight_[s] = int32_t(lights_.size());
        Light light;
        light.kind = LightKind::Sphere;
        light.radiance = sphere.emission.radiance;
        light.twoSided = sphere.emission.twoSided;
        light.center = sphere.center;
        light.radius = sphere.radius;
        light.texture = sphere.emission.texture.get();
        lights_.push_back(light);
        emitterSizes.push_back(1);
        const double area = 4.0 * kPi * double(sphere.radius) * sphere.radius;
        power.push_back(double(light.radiance.luminance()) * area * kPi * (light.twoSided ? 2 : 1));
    }
    for (const PointLight& point : pointLights) {
        Light light;
        light.kind = LightKind::Point;
        light.radiance = point.intensity;
        light.center = point.position;
        lights_.push_back(light);
        emitterSizes.push_back(1);
        power.push_back(4.0 * kPi * double(point.intensity.luminance()));
    }
    for (const SpotLight& spot : spotLights) {
        Light light;
        light.kind = LightKind::Spot;
        light.radiance = spot.intensity;
        light.center = spot.position;
        light.normal = spot.direction;
        light.cosFalloffStart = spot.cosFalloffStart;
        light.cosFalloffEnd = spot.cosFalloffEnd;
        lights_.push_back(light);
        emitterSizes.push_back(1);
        power.push_back(spot.solidAngle() * double(spot.intensity.luminance()));
    }
    const double sceneRadius = sceneBoundingRadius(scene);
    for (const DirectionalLight& directional : directionalLights) {
        Light light;
        light.kind = LightKind::Directional;
        light.radiance = directional.irradiance;
        light.normal = directional.direction;
        lights_.push_back(light);
        emitterSizes.push_back(1);
        // The power crossing a disk the size of the scene (pbrt-v4's DistantLight::Phi).
        power.push_back(kPi * sceneRadius * sceneRadius * double(directional.irradiance.luminance()));
    }
    if (!environment_.isBlack()) {
        environmentLight_ = int32_t(lights_.size());
        Light light;
        light.kind = LightKind::Environment;
        lights_.push_back(light);
        emitterSizes.push_back(1);
        // Power through a disk the size of the scene, from every direction (pbrt-v4's estimate),
        // with the radiance averaged over the sphere.
        power.push_back(4.0 * kPi * kPi * sceneRadius * sceneRadius *
                        double(environment_.average().luminance()));
    }
    for (const Light& light : lights_)
        hasAreaLights_ |= light.kind == LightKind::Triangle || light.kind == LightKind::Sphere;
    choice_ = DiscreteDistribution(power);
    drawsSampleValues_ = lights_.size() > 1 || (lights_.size() == 1 && !isDelta(0));

    groupEmitters(emitterSizes, power);
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
    if (lights_.size() <= kMaxLocallyChosenEmitters) emitterSizes.assign(lights_.size(), 1);
    // Beyond the batch's capacity the choice stays by power (a light tree's work), and nothing
    // below is needed.
    if (choice_.empty() || emitterSizes.size() > kMaxLocallyChosenEmitters) return;
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
        bounds_.set(e, size == 1 ? lightBounds(lights_[first], float(emitterPower))
                                 : meshBounds(&lights_[first], size, float(emitterPower)));
    }
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
    uPoint.x = std::clamp((target - chosenStart) / weight, 0.0f, 0x1.fffffep-1f);
    const Emitter& emitter = emitters_[chosen];
    const uint32_t light = emitter.firstLight + emitter.withinEmitter.sampleAndRemap(uPoint.x);
    return {light, weight / total * probabilityWithinEmitter_[light]};
}

float LightSet::localChoiceProbability(uint32_t light, Vec3f p, Vec3f n) const {
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
    const float choicePdf = choice.probability;
    const uint32_t index = choice.light;
    const Light& light = lights_[index];
    Vec2f uv{0.0f, 0.0f};  // the sampled point's surface coordinates, for textured emission
    switch (light.kind) {
        case LightKind::Point:
        case LightKind::Spot: {
            const std::optional<LightSample> point = samplePoint(choice, reference);
            if (!point) return false;
            ls = *point;
            if (light.kind == LightKind::Spot)
                ls.radiance *=
                    spotFalloff(-dot(ls.direction, light.normal), light.cosFalloffStart, light.cosFalloffEnd);
            return true;
        }
        case LightKind::Directional: {
            ls.direction = -light.normal;
            ls.distance = std::numeric_limits<float>::infinity();
            ls.radiance = light.radiance;
            ls.pdf = choicePdf;
            ls.isDelta = true;
            return true;
        }
        case LightKind::Environment: {
            const std::optional<EnvironmentSample> es = environment_.sample(u);
            if (!es) return false;
            ls.direction = es->direction;
            ls.distance = std::numeric_limits<float>::infinity();
            ls.radiance = es->radiance;
            ls.pdf = choicePdf * es->pdf;
            ls.isDelta = false;
            return true;
        }
        case LightKind::Triangle: {
            const Vec2f b = sampleUniformTriangle(u);
            ls.point = light.p0 * (1.0f - b.x - b.y) + light.p1 * b.x + light.p2 * b.y;
            // As for a hit's barycentric interpolation (geometry/surface_interaction.h).
            ls.pointError =
                (abs(light.p0 * (1.0f - b.x - b.y)) + abs(light.p1 * b.x) + abs(light.p2 * b.y)) * gamma(7);
            ls.lightNormal = light.normal;
            if (light.texture) uv = light.uv0 * (1.0f - b.x - b.y) + light.uv1 * b.x + light.uv2 * b.y;
            break;
        }
        case LightKind::Sphere: {
            const Vec3f toCenter = light.center - reference;
            const float distanceSquared = lengthSquared(toCenter);
            const float radiusSquared = light.radius * light.radius;
            if (distanceSquared <= radiusSquared * 1.0001f) {
                // Inside (or on) the sphere: every point is visible, sample by area.
                ls.lightNormal = sampleUniformSphere(u);
                ls.point = light.center + ls.lightNormal * light.radius;
                ls.pointError = (abs(light.center) + abs(ls.lightNormal * light.radius)) * gamma(8);
            } else {
                // Outside: sample the cone of directions the sphere subtends (pbrt-v4's
                // Sphere::Sample), then find the point on the sphere that direction hits first.
                const float distance = std::sqrt(distanceSquared);
                const float sinThetaMax = light.radius / distance;
                const float sin2ThetaMax = sinThetaMax * sinThetaMax;
                const float cosThetaMax = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaMax));
                float cosTheta = (cosThetaMax - 1.0f) * u.x + 1.0f;
                float sin2Theta = 1.0f - cosTheta * cosTheta;
                if (sin2ThetaMax < 0.00068523f) {  // below ~1.5 degrees: Taylor expansion keeps precision
                    sin2Theta = sin2ThetaMax * u.x;
                    cosTheta = std::sqrt(1.0f - sin2Theta);
                }
                const float cosAlpha = sin2Theta / sinThetaMax +
                                       cosTheta * std::sqrt(std::max(0.0f, 1.0f - sin2Theta / sin2ThetaMax));
                const float sinAlpha = std::sqrt(std::max(0.0f, 1.0f - cosAlpha * cosAlpha));
                const Vec2f azimuth = cosSinTurn(u.y);
                const Frame frame = Frame::fromNormal(toCenter / distance);
                // Angle alpha is measured at the centre, from the direction back to the reference.
                const Vec3f fromCenter =
                    frame.toWorld({sinAlpha * azimuth.x, sinAlpha * azimuth.y, -cosAlpha});
                ls.lightNormal = normalize(fromCenter);
                ls.point = light.center + ls.lightNormal * light.radius;
                ls.pointError = (abs(light.center) + abs(ls.lightNormal * light.radius)) * gamma(8);
            }
            break;
        }
    }
    const Vec3f toLight = ls.point - reference;
    const float distanceSquared = lengthSquared(toLight);
    if (!(distanceSquared > 0.0f)) return false;
    ls.distance = std::sqrt(distanceSquared);
    ls.direction = toLight / ls.distance;
    const float cosAtLight = dot(ls.lightNormal, -ls.direction);
    if (light.kind == LightKind::Sphere && light.texture) uv = sphereUv(ls.lightNormal);
    const Rgb radiance = light.texture ? emittedRadiance(*light.texture, uv) : light.radiance;
    ls.radiance = (cosAtLight > 0.0f || light.twoSided) ? radiance : Rgb(0.0f);
    // A triangle's density from the distance and cosine at hand (solidAnglePdf, which pdfOfHit
    // uses, computes them again; the two differ by rounding only).
    const float pointPdf = light.kind == LightKind::Triangle
                               ? areaToSolidAnglePdf(distanceSquared, std::abs(cosAtLight), light.area)
                               : solidAnglePdf(light, reference, ls.point);
    ls.pdf = choicePdf * pointPdf;
    ls.isDelta = false;
    return ls.pdf > 0.0f && std::isfinite(ls.pdf);
}

float LightSet::solidAnglePdf(const Light& light, Vec3f reference, Vec3f point) const {
    const Vec3f toPoint = point - reference;
    const float distanceSquared = lengthSquared(toPoint);
    switch (light.kind) {
        case LightKind::Triangle: {
            const float cosAtLight = std::abs(dot(light.normal, toPoint)) / std::sqrt(distanceSquared);
            return areaToSolidAnglePdf(distanceSquared, cosAtLight, light.area);
        }
        case LightKind::Sphere: {
            const float centerDistanceSquared = lengthSquared(light.center - reference);
            const float radiusSquared = light.radius * light.radius;
            if (centerDistanceSquared <= radiusSquared * 1.0001f) {
                const Vec3f normal = normalize(point - light.center);
                const float cosAtLight = std::abs(dot(normal, toPoint)) / std::sqrt(distanceSquared);
                return areaToSolidAnglePdf(distanceSquared, cosAtLight, 4.0f * kPi * radiusSquared);
            }
            const float sin2ThetaMax = radiusSquared / centerDistanceSquared;
            const float cosThetaMax = std::sqrt(std::max(0.0f, 1.0f - sin2ThetaMax));
            // Same small-angle expansion as in sample(): 1 - cos(theta_max) ~ sin^2 / 2.
            const float oneMinusCos = sin2ThetaMax < 0.00068523f ? 0.5f * sin2ThetaMax : 1.0f - cosThetaMax;
            return 1.0f / (2.0f * kPi * oneMinusCos);
        }
        case LightKind::Point:
        case LightKind::Spot:
        case LightKind::Directional:
        case LightKind::Environment:
            return 0.0f;  // not sampled by solid angle around a point
    }
    return 0.0f;
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
            return -1;  // instances never emit (the scene loader refuses it)
    }
    return -1;
}

Rgb LightSet::emittedByAreaLight(const SurfaceInteraction& si, Vec3f towardsViewer) const {
    const int32_t index = lightIndexOf(si.shape);
    if (index < 0) return Rgb(0.0f);
    const Light& light = lights_[index];
    if (light.twoSided || dot(si.geometricNormal, towardsViewer) > 0.0f)
        return light.texture ? emittedRadiance(*light.texture, si.uv) : light.radiance;
    return Rgb(0.0f);
}

float LightSet::pdfOfHit(Vec3f reference, Vec3f referenceNormal, const SurfaceInteraction& si) const {
    const int32_t index = lightIndexOf(si.shape);
    if (index < 0) return 0.0f;
    return choiceProbability(uint32_t(index), reference, referenceNormal) *
           solidAnglePdf(lights_[index], reference, si.position);
}

float LightSet::pdfOfEnvironment(Vec3f reference, Vec3f referenceNormal, Vec3f direction) const {
    if (environmentLight_ < 0) return 0.0f;
    return choiceProbability(uint32_t(environmentLight_), reference, referenceNormal) *
           environment_.pdf(direction);
}

}  // namespace penumbra
