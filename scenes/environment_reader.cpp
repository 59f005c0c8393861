#include "scenes/environment_reader.h"

#include <fmt/format.h>

#include <array>

#include "core/error.h"
#include "core/transform.h"
#include "scenes/type_table.h"
#include "textures/image_file.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

EnvironmentLight readConstantEnvironment(const JsonValue& value, const fs::path&) {
    return EnvironmentLight::constant(value.requiredMember("radiance").rgb(0.0f));
}

// An equirectangular image (lights/environment_light.h has its orientation), scaled and rotated.
EnvironmentLight readImageEnvironment(const JsonValue& value, const fs::path& folder) {
    const JsonValue fileValue = value.requiredMember("file");
    const fs::path path = fileValue.existingFile(folder, "image");
    Rgb scale(1.0f);
    if (auto v = value.member("scale")) scale = v->rgb(0.0f);
    Transform rotation;
    if (auto v = value.member("rotate")) {
        const JsonObject rotate(*v, {"axis", "degrees"});
        const JsonValue axisValue = rotate.require("axis");
        const Vec3f axis = axisValue.vec3();
        if (!(lengthSquared(axis) > 0.0f)) axisValue.failExpected("a non-zero axis");
        rotation = Transform::rotate(rotate.require("degrees").number(), axis);
    }
    // A map made for the other handedness (pbrt's latitude-longitude maps): the image's columns
    // run the other way round, a reflection of the light's own x before `rotate`.
    if (auto v = value.member("mirror"); v && v->boolean())
        rotation = rotation * Transform::scale({-1.0f, 1.0f, 1.0f});
    SourceLocation where;
    where.file = fileValue.file();
    where.jsonPointer = fileValue.pointer();
    LinearRgbImage image = readLinearRgbImage(path, where);
    EnvironmentMapping mapping = EnvironmentMapping::Equirectangular;
    if (auto v = value.member("mapping")) {
        if (v->choice({"equirectangular", "equal_area"}) == 1) mapping = EnvironmentMapping::EqualArea;
        if (mapping == EnvironmentMapping::EqualArea && image.width != image.height)
            v->fail(fmt::format("an equal-area map is a square image; {} is {}x{}", path.string(),
                                image.width, image.height));
    }
    return EnvironmentLight::fromImage(
        EnvironmentImage{image.width, image.height, std::move(image.texels), mapping}, scale, rotation);
}

using EnvironmentReader = EnvironmentLight (*)(const JsonValue&, const fs::path&);

const std::array<TypeRow<EnvironmentReader>, 2> kEnvironmentTypes{{
    {"constant", {"type", "radiance"}, readConstantEnvironment},
    {"image", {"type", "file", "mapping", "scale", "rotate", "mirror"}, readImageEnvironment},
}};

}  // namespace

EnvironmentLight readBackground(const JsonValue& value) {
    return EnvironmentLight::constant(value.rgb(0.0f));
}

EnvironmentLight readEnvironment(const JsonValue& value, const fs::path& folder) {
    return findTypeRow<EnvironmentReader>(value, kEnvironmentTypes).read(value, folder);
}

}  // namespace penumbra
