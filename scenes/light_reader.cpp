#include "scenes/light_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <memory>
#include <numbers>

#include "core/frame.h"
#include "lights/goniometric_light.h"
#include "lights/ies_profile.h"
#include "scenes/type_table.h"
#include "textures/image_file.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

void readPointLight(const JsonValue& value, const fs::path&, Scene& scene) {
    PointLight light;
    light.position = value.requiredMember("position").vec3();
    light.intensity = value.requiredMember("intensity").rgb(0.0f);
    scene.lights.push_back(light);
}

// A spot light: "cone_angle" from the axis to where the light ends, "cone_delta" the band inside it
// over which it falls off (pbrt-v4's coneangle and conedelta, in degrees).
void readSpotLight(const JsonValue& value, const fs::path&, Scene& scene) {
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

void readDirectionalLight(const JsonValue& value, const fs::path&, Scene& scene) {
    const JsonValue directionValue = value.requiredMember("direction");
    const Vec3f direction = directionValue.vec3();
    if (!(lengthSquared(direction) > 0.0f)) directionValue.failExpected("a non-zero direction");
    scene.lights.push_back(
        DirectionalLight{normalize(direction), value.requiredMember("irradiance").rgb(0.0f)});
}

// A goniometric light's profile: an IES file (by its extension, .ies), otherwise a square image
// in the equal-area map (pbrt-v4's goniometric images).
IntensityProfile readIntensityProfile(const JsonValue& fileValue, const fs::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (extension == ".ies") return readIesProfile(path);
    SourceLocation where;
    where.file = fileValue.file();
    where.jsonPointer = fileValue.pointer();
    const LinearRgbImage image = readLinearRgbImage(path, where);
    if (image.width != image.height)
        fileValue.fail(
            fmt::format("the image {} is {}x{}: a goniometric light's image is square (an equal-area "
                        "map of the sphere, as pbrt-v4's), or give an IES file (.ies)",
                        path.string(), image.width, image.height));
    return IntensityImage(image.width, image.texels);
}

// A goniometric light: a point light with a photometric profile ("file": IES, or an image), its axis
// ("nadir", the profile's vertical angle 0; straight down by default) and the direction of its horizontal
// angle 0 ("front"; by default the one Frame::fromNormal(nadir) gives), its candela scaled by
// "scale" into W/sr per channel.
void readGoniometricLight(const JsonValue& value, const fs::path& folder, Scene& scene) {
    GoniometricLight light;
    light.position = value.requiredMember("position").vec3();
    const JsonValue fileValue = value.requiredMember("file");
    const fs::path path = fileValue.existingFile(folder, "profile");
    light.profile = std::make_shared<const IntensityProfile>(readIntensityProfile(fileValue, path));
    Vec3f nadir{0.0f, -1.0f, 0.0f};
    if (auto v = value.member("nadir")) {
        nadir = v->vec3();
        if (!(lengthSquared(nadir) > 0.0f)) v->failExpected("a non-zero direction");
    }
    Vec3f front = Frame::fromNormal(normalize(nadir)).s;
    if (auto v = value.member("front")) {
        front = v->vec3();
        if (!(lengthSquared(cross(front, normalize(nadir))) > 1e-12f * lengthSquared(front)))
            v->failExpected("a direction not parallel to the nadir");
    }
    light.frame = GoniometricLight::profileFrame(nadir, front);
    if (auto v = value.member("scale")) light.scale = v->rgb(0.0f);
    // pbrt-v4's "power": the scale times power / the profile's flux.
    if (auto v = value.member("power")) {
        const float power = v->numberAbove(0.0f);
        const double flux = profileFlux(*light.profile);
        if (!(flux > 0.0)) v->fail("the profile emits no light, so no power can be given to it");
        light.scale *= float(double(power) / flux);
    }
    scene.lights.push_back(std::move(light));
}

using LightReader = void (*)(const JsonValue&, const fs::path&, Scene&);

const std::array<TypeRow<LightReader>, 4> kLightTypes{{
    {"point", {"type", "position", "intensity"}, readPointLight},
    {"spot", {"type", "position", "direction", "intensity", "cone_angle", "cone_delta"}, readSpotLight},
    {"directional", {"type", "direction", "irradiance"}, readDirectionalLight},
    {"goniometric", {"type", "position", "file", "nadir", "front", "scale", "power"}, readGoniometricLight},
}};

}  // namespace

void readLights(const JsonValue& section, const fs::path& folder, Scene& scene) {
    for (const JsonValue& light : section.elements())
        findTypeRow<LightReader>(light, kLightTypes).read(light, folder, scene);
}

}  // namespace penumbra
