#include "scenes/light_reader.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>

#include "scenes/type_table.h"

namespace penumbra {

namespace {

void readPointLight(const JsonValue& value, Scene& scene) {
    PointLight light;
    light.position = value.requiredMember("position").vec3();
    light.intensity = value.requiredMember("intensity").rgb(0.0f);
    scene.lights.push_back(light);
}

// A spot light: "cone_angle" from the axis to where the light ends, "cone_delta" the band inside it
// over which it falls off (pbrt-v4's coneangle and conedelta, in degrees).
void readSpotLight(const JsonValue& value, Scene& scene) {
    SpotLight light;
    light.position = value.requiredMember("position").vec3();
    const JsonValue directionValue = value.requiredMember("direction");
    const Vec3f direction = directionValue.vec3();
    if (!(lengthSquared(direction) > 0.0f)) directionValue.failExpected("a non-zero direction");
    light.direction = normalize(direction);
    light.intensity = value.requiredMember("intensity").rgb(0.0f);
    float coneAngle = 30.0f, coneDelta = 5.0f;
    if (auto v = value.member("cone_angle")) {
        coneAngle = v->number();
        if (!(coneAngle > 0.0f && coneAngle <= 180.0f))
            v->failExpected("an angle in degrees greater than 0 and at most 180");
    }
    if (auto v = value.member("cone_delta")) {
        coneDelta = v->number();
        if (!(coneDelta >= 0.0f && coneDelta <= coneAngle))
            v->failExpected(fmt::format("an angle in degrees from 0 to the cone_angle ({})", coneAngle));
    }
    constexpr double kRadians = std::numbers::pi / 180.0;
    light.cosFalloffEnd = float(std::cos(double(coneAngle) * kRadians));
    light.cosFalloffStart = float(std::cos(double(coneAngle - coneDelta) * kRadians));
    scene.lights.push_back(light);
}

void readDirectionalLight(const JsonValue& value, Scene& scene) {
    const JsonValue directionValue = value.requiredMember("direction");
    const Vec3f direction = directionValue.vec3();
    if (!(lengthSquared(direction) > 0.0f)) directionValue.failExpected("a non-zero direction");
    scene.lights.push_back(
        DirectionalLight{normalize(direction), value.requiredMember("irradiance").rgb(0.0f)});
}

using LightReader = void (*)(const JsonValue&, Scene&);

const std::array<TypeRow<LightReader>, 3> kLightTypes{{
    {"point", {"type", "position", "intensity"}, readPointLight},
    {"spot", {"type", "position", "direction", "intensity", "cone_angle", "cone_delta"}, readSpotLight},
    {"directional", {"type", "direction", "irradiance"}, readDirectionalLight},
}};

}  // namespace

void readLights(const JsonValue& section, Scene& scene) {
    for (const JsonValue& light : section.elements())
        findTypeRow<LightReader>(light, kLightTypes).read(light, scene);
}

}  // namespace penumbra
