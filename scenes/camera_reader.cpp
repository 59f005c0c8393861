#include "scenes/camera_reader.h"

#include <fmt/format.h>

#include <array>

#include "cameras/aperture.h"
#include "cameras/lens_file.h"
#include "core/error.h"
#include "core/input_limits.h"
#include "core/transform.h"
#include "scenes/type_table.h"
#include "textures/image_file.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// The look_from / look_at / up members of `value` (whose keys the caller has checked).
CameraPose readCameraPose(const JsonValue& value, const CameraPose& defaults) {
    CameraPose pose = defaults;
    if (auto v = value.member("look_from")) pose.lookFrom = v->vec3();
    if (auto v = value.member("look_at")) pose.lookAt = v->vec3();
    if (auto v = value.member("up")) pose.up = v->vec3();
    if (!Transform::lookAt(pose.lookFrom, pose.lookAt, pose.up))
        value.fail(
            "look_from and look_at must differ, and up must be non-zero and not parallel to the "
            "viewing direction");
    return pose;
}

// "aperture": one of pbrt-v4's built-in shapes, or an image file whose channels are averaged.
ApertureImage readApertureShape(const JsonValue& value, const fs::path& folder) {
    const std::string name = value.string();
    if (auto builtin = builtinApertureImage(name)) return *builtin;
    if (name.find_first_of("./\\") == std::string::npos)
        value.failExpected("\"gaussian\", \"square\", \"pentagon\", \"star\" or the name of an image file");
    const fs::path path = value.existingFile(folder, "aperture image");
    SourceLocation where;
    where.file = value.file();
    where.jsonPointer = value.pointer();
    const LinearRgbImage image = readLinearRgbImage(path, where);
    ApertureImage aperture{image.width, image.height, {}};
    aperture.values.reserve(image.texels.size());
    for (const Rgb& texel : image.texels) aperture.values.push_back((texel.r + texel.g + texel.b) / 3.0f);
    try {
        normalizeApertureImage(aperture);
    } catch (const InputError&) {
        value.fail(fmt::format("the aperture image {} is black: no light would pass", path.string()));
    }
    return aperture;
}

// The thin lens of the perspective and orthographic cameras: its size, shape and focus.
void readThinLens(const JsonValue& value, const fs::path& folder, CameraParams& camera,
                  bool withFocalLength) {
    const auto fNumber = value.member("f_number"), focalLength = value.member("focal_length");
    if (auto v = value.member("aperture_radius")) {
        if (fNumber) fNumber->fail("give either aperture_radius or f_number with focal_length, not both");
        camera.apertureRadius = v->numberInRange(0.0f, limits::kMaxCoordinate);
    } else if (withFocalLength && (fNumber || focalLength)) {
        // The aperture as an f-number with the lens's focal length (radius = f / 2N).
        if (!fNumber) value.fail("focal_length needs f_number to define the aperture");
        if (!focalLength) value.fail("f_number needs focal_length (in scene units) to define the aperture");
        camera.apertureRadius = focalLength->numberAbove(0.0f) / (2.0f * fNumber->numberAbove(0.0f));
        if (!(camera.apertureRadius <= limits::kMaxCoordinate))
            fNumber->fail(
                fmt::format("focal_length / (2 f_number) gives an aperture radius of {}, beyond the limit "
                            "of {:g} (docs/limits.md)",
                            camera.apertureRadius, limits::kMaxCoordinate));
    }
    if (auto v = value.member("aperture_blades")) {
        camera.apertureBlades = int(v->integer(0, 64));
        if (camera.apertureBlades == 1 || camera.apertureBlades == 2)
            v->failExpected("0 (a round aperture) or 3 to 64 blades");
    }
    if (auto v = value.member("aperture_rotation")) camera.apertureRotationDegrees = v->number();
    if (auto v = value.member("aperture")) {
        if (value.member("aperture_blades"))
            v->fail("give either aperture (a shape) or aperture_blades, not both");
        camera.apertureImage = readApertureShape(*v, folder);
    }
}

// Focus: a distance along the view direction, or a point to focus on; by default look_at.
void readFocus(const JsonValue& value, CameraParams& camera) {
    if (auto v = value.member("focus_distance")) {
        if (value.member("focus_on")) v->fail("give either focus_distance or focus_on, not both");
        camera.focusDistance = v->numberAbove(0.0f);
        if (camera.focusDistance > limits::kMaxCoordinate)
            v->failExpected(fmt::format("a number > 0 and <= {:g}", limits::kMaxCoordinate));
    } else if (auto v = value.member("focus_on")) {
        const Vec3f view = normalize(camera.lookAt - camera.lookFrom);
        camera.focusDistance = dot(v->vec3() - camera.lookFrom, view);
        if (!(camera.focusDistance > 0.0f)) v->fail("the point to focus on must lie in front of the camera");
    }
}

void readPerspective(const JsonValue& value, const fs::path& folder, CameraParams& camera) {
    if (auto v = value.member("fov")) {
        if (!v->json().is_number() || !(v->number() > 0.0f && v->number() < 180.0f))
            v->failExpected("a vertical field of view in degrees, greater than 0 and less than 180");
        camera.verticalFovDegrees = v->number();
    }
    readThinLens(value, folder, camera, true);
    readFocus(value, camera);
}

void readOrthographic(const JsonValue& value, const fs::path& folder, CameraParams& camera) {
    camera.projection = CameraProjection::Orthographic;
    if (auto v = value.member("height")) {
        camera.orthographicHeight = v->numberAbove(0.0f);
        if (camera.orthographicHeight > limits::kMaxCoordinate)
            v->failExpected(fmt::format("a height > 0 and <= {:g}", limits::kMaxCoordinate));
    }
    readThinLens(value, folder, camera, false);
    readFocus(value, camera);
}

void readSpherical(const JsonValue& value, const fs::path&, CameraParams& camera) {
    camera.projection = CameraProjection::Spherical;
    if (auto v = value.member("mapping"))
        camera.sphericalMapping = v->choice({"equirectangular", "equal_area"}) == 0
                                      ? SphericalMapping::Equirectangular
                                      : SphericalMapping::EqualArea;
    if (auto v = value.member("mirror")) camera.mirrorColumns = v->boolean();
}

void readFisheye(const JsonValue& value, const fs::path&, CameraParams& camera) {
    camera.projection = CameraProjection::Fisheye;
    camera.verticalFovDegrees = 180.0f;
    if (auto v = value.member("fov")) {
        if (!v->json().is_number() || !(v->number() > 0.0f && v->number() <= 360.0f))
            v->failExpected("the field of view across the image's shorter side in degrees, > 0 and <= 360");
        camera.verticalFovDegrees = v->number();
    }
    if (auto v = value.member("mapping"))
        camera.fisheyeMapping = v->choice({"equidistant", "equisolid"}) == 0 ? FisheyeMapping::Equidistant
                                                                             : FisheyeMapping::Equisolid;
}

void readLensSystem(const JsonValue& value, const fs::path& folder, CameraParams& camera) {
    camera.projection = CameraProjection::LensSystem;
    LensSystemParams& lens = camera.lensSystem;
    const JsonValue file = value.requiredMember("lens_file");
    const fs::path path = file.existingFile(folder, "lens file");
    lens.surfaces = readLensFile(path);
    if (auto v = value.member("aperture_diameter")) lens.apertureDiameterMm = v->numberAbove(0.0f);
    if (auto v = value.member("film_diagonal")) lens.filmDiagonalMm = v->numberInRange(1e-3f, 1e4f);
    if (auto v = value.member("scene_unit_mm")) lens.mmPerSceneUnit = v->numberInRange(1e-6f, 1e9f);
    if (auto v = value.member("aperture")) camera.apertureImage = readApertureShape(*v, folder);
    readFocus(value, camera);
}

using CameraReader = void (*)(const JsonValue&, const fs::path&, CameraParams&);

const std::vector<std::string_view> kPoseKeys{
    "type", "look_from", "look_at", "up", "shutter", "motion", "medium"};  // "medium": read with the media

std::vector<std::string_view> poseKeysAnd(std::initializer_list<std::string_view> keys) {
    std::vector<std::string_view> all = kPoseKeys;
    all.insert(all.end(), keys);
    return all;
}

const std::array<TypeRow<CameraReader>, 5> kCameraTypes{{
    {"perspective",
     poseKeysAnd({"fov", "aperture_radius", "f_number", "focal_length", "aperture_blades",
                  "aperture_rotation", "aperture", "focus_distance", "focus_on"}),
     readPerspective},
    {"orthographic",
     poseKeysAnd({"height", "aperture_radius", "aperture_blades", "aperture_rotation", "aperture",
                  "focus_distance", "focus_on"}),
     readOrthographic},
    {"spherical", poseKeysAnd({"mapping", "mirror"}), readSpherical},
    {"fisheye", poseKeysAnd({"fov", "mapping"}), readFisheye},
    {"lens_system",
     poseKeysAnd({"lens_file", "aperture_diameter", "film_diagonal", "scene_unit_mm", "aperture",
                  "focus_distance", "focus_on"}),
     readLensSystem},
}};

}  // namespace

CameraParams readCamera(const JsonValue& value, const fs::path& folder) {
    // Without a type, a perspective camera.
    const TypeRow<CameraReader>& row =
        value.member("type") ? findTypeRow<CameraReader>(value, kCameraTypes) : kCameraTypes[0];
    const JsonObject checked(value, row.keys);
    CameraParams camera;
    const CameraPose pose = readCameraPose(value, {camera.lookFrom, camera.lookAt, camera.up});
    camera.lookFrom = pose.lookFrom;
    camera.lookAt = pose.lookAt;
    camera.up = pose.up;
    row.read(value, folder, camera);

    if (auto v = value.member("shutter")) {
        if (!v->json().is_array() || v->json().size() != 2)
            v->failExpected("an array [open, close] of 2 numbers");
        camera.shutterOpen = v->element(0).number();
        camera.shutterClose = v->element(1).number();
        if (camera.shutterClose < camera.shutterOpen) v->failExpected("[open, close] with close >= open");
    }
    if (auto v = value.member("motion")) {
        if (v->arraySize() < 2)
            v->failExpected("an array of at least 2 camera poses, evenly spaced over the shutter");
        // Each pose starts from the camera's own and changes what it names.
        for (const JsonValue& poseValue : v->elements()) {
            const JsonObject poseObject(poseValue, {"look_from", "look_at", "up"});
            camera.motion.push_back(readCameraPose(poseValue, pose));
        }
    }
    return camera;
}

}  // namespace penumbra
