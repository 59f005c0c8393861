// The closed set of lights: a std::variant of the light models, each a small value type in a header
// of its own with the same members (the LightModelType concept). The scene names the point, spot,
// goniometric and directional lights (Scene::lights); the light set (light_set.h) adds an area
// light for each emitting triangle and sphere, and the environment.
#pragma once

#include <concepts>
#include <variant>

#include "core/vec.h"
#include "lights/directional_light.h"
#include "lights/environment_light.h"
#include "lights/goniometric_light.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"
#include "lights/point_light.h"
#include "lights/sphere_light.h"
#include "lights/spot_light.h"
#include "lights/triangle_light.h"

namespace penumbra {

// What every light model provides:
//  - kIsDelta: its light comes from a point or along one direction, which rays never hit, so that
//    next-event estimation alone finds it (sample() ignores u);
//  - kIsInfinite: it is infinitely far (directional, environment), chosen by its share of the power;
//  - kPointIndependentOfReference: sample() picks the same point for the same u from any reference
//    (a point light's position, a triangle's uniform area sample; not a sphere's visible cap), so a
//    point can be chosen before the reference it lights (equiangular sampling in media);
//  - power(sceneRadius): its power in luminance, by which a light is chosen (infinite lights: through
//    a disk of the scene's radius, as pbrt-v4 estimates it);
//  - bounds(power): the bounds by which a finite light is chosen at a vertex (light_bounds.h);
//  - sample(reference, u, ls): light arriving at `reference` from a point (or along a direction) of
//    the light, its pdf per solid angle (1 for delta lights), false where there is none;
//  - pdf(reference, towards): the solid-angle density with which sample() produces the point
//    `towards` (for infinite lights, the direction `towards`); 0 for delta lights.
template <class L>
concept LightModelType = requires(const L& light, Vec3f p, Vec2f u, LightSample& ls, double sceneRadius,
                                  float power) {
    { L::kIsDelta } -> std::convertible_to<bool>;
    { L::kIsInfinite } -> std::convertible_to<bool>;
    { L::kPointIndependentOfReference } -> std::convertible_to<bool>;
    { light.power(sceneRadius) } -> std::same_as<double>;
    { light.bounds(power) } -> std::same_as<LightBounds>;
    { light.sample(p, u, ls) } -> std::same_as<bool>;
    { light.pdf(p, p) } -> std::same_as<float>;
};

// The order is the light set's: area lights, then the ones the scene names, finite before infinite.
using LightModel = std::variant<TriangleLight, SphereLight, PointLight, SpotLight, GoniometricLight,
                                DirectionalLight, EnvironmentEmitter>;

namespace detail {
template <class Variant>
struct AllLightModels;
template <class... Models>
struct AllLightModels<std::variant<Models...>> {
    static constexpr bool value = (LightModelType<Models> && ...);
};
}  // namespace detail
static_assert(detail::AllLightModels<LightModel>::value, "every light model satisfies LightModelType");

inline bool isDeltaLight(const LightModel& light) {
    return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::kIsDelta; }, light);
}
inline bool isInfiniteLight(const LightModel& light) {
    return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::kIsInfinite; }, light);
}
inline bool isPointIndependentOfReference(const LightModel& light) {
    return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::kPointIndependentOfReference; },
                      light);
}

}  // namespace penumbra
