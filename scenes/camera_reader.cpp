#include "scenes/camera_reader.h"

#include <fmt/format.h>

#include "core/input_limits.h"
#include "core/transform.h"

namespace penumbra {

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

}  // namespace

ThinLensCameraParams readCamera(const JsonValue& value) {
    const JsonObject object(
        value, {"look_from", "look_at", "up", "fov", "aperture_radius", "f_number", "focal_length",
                "aperture_blades", "aperture_rotation", "focus_distance", "focus_on", "shutter", "motion",
                "medium"});  // "medium": read with the media (scenes/medium_reader.h)
    ThinLensCameraParams camera;
    const CameraPose pose = readCameraPose(value, {camera.lookFrom, camera.lookAt, camera.up});
    camera.lookFrom = pose.lookFrom;
    camera.lookAt = pose.lookAt;
    camera.up = pose.up;
    if (auto v = object.get("fov")) {
        if (!v->json().is_number() || !(v->number() > 0.0f && v->number() < 180.0f))
            v->failExpected("a vertical field of view in degrees, greater than 0 and less than 180");
        camera.verticalFovDegrees = v->number();
    }

    // The aperture: a lens radius, or an f-number with the lens's focal length (radius = f / 2N).
    const auto fNumber = object.get("f_number"), focalLength = object.get("focal_length");
    if (auto v = object.get("aperture_radius")) {
        if (fNumber) fNumber->fail("give either aperture_radius or f_number with focal_length, not both");
        camera.apertureRadius = v->numberInRange(0.0f, limits::kMaxCoordinate);
    } else if (fNumber || focalLength) {
        if (!fNumber) value.fail("focal_length needs f_number to define the aperture");
        if (!focalLength) value.fail("f_number needs focal_length (in scene units) to define the aperture");
        camera.apertureRadius = focalLength->numberAbove(0.0f) / (2.0f * fNumber->numberAbove(0.0f));
        if (!(camera.apertureRadius <= limits::kMaxCoordinate))
            fNumber->fail(
                fmt::format("focal_length / (2 f_number) gives an aperture radius of {}, beyond the limit "
                            "of {:g} (docs/limits.md)",
                            camera.apertureRadius, limits::kMaxCoordinate));
    }
    if (auto v = object.get("aperture_blades")) {
        camera.apertureBlades = int(v->integer(0, 64));
        if (camera.apertureBlades == 1 || camera.apertureBlades == 2)
            v->failExpected("0 (a round aperture) or 3 to 64 blades");
    }
    if (auto v = object.get("aperture_rotation")) camera.apertureRotationDegrees = v->number();

    // Focus: a distance along the view direction, or a point to focus on; by default look_at.
    if (auto v = object.get("focus_distance")) {
        if (object.get("focus_on")) v->fail("give either focus_distance or focus_on, not both");
        camera.focusDistance = v->numberAbove(0.0f);
        if (camera.focusDistance > limits::kMaxCoordinate)
            v->failExpected(fmt::format("a number > 0 and <= {:g}", limits::kMaxCoordinate));
    } else if (auto v = object.get("focus_on")) {
        const Vec3f view = normalize(camera.lookAt - camera.lookFrom);
        camera.focusDistance = dot(v->vec3() - camera.lookFrom, view);
        if (!(camera.focusDistance > 0.0f)) v->fail("the point to focus on must lie in front of the camera");
    }

    if (auto v = object.get("shutter")) {
        if (!v->json().is_array() || v->json().size() != 2)
            v->failExpected("an array [open, close] of 2 numbers");
        camera.shutterOpen = v->element(0).number();
        camera.shutterClose = v->element(1).number();
        if (camera.shutterClose < camera.shutterOpen) v->failExpected("[open, close] with close >= open");
    }
    if (auto v = object.get("motion")) {
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
