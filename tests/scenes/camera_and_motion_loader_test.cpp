// Loading the distribution-ray-tracing fields: lens, focus, shutter and motion keys, and the
// errors for impossible values, each naming the field.
#include <gtest/gtest.h>

#include <cmath>

#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

const char* kMaterials = R"("materials": {"grey": {"type": "lambert"}})";

Scene parse(const std::string& body) { return parseScene("{" + body + "}", "scene.json"); }

TEST(CameraFields, FNumberAndFocalLengthGiveTheLensRadius) {
    const Scene scene = parse(R"("camera": {"look_at": [0, 0, -5], "f_number": 2, "focal_length": 0.05})");
    EXPECT_FLOAT_EQ(scene.camera.apertureRadius, 0.05f / 4.0f);
}

TEST(CameraFields, FocusOnAPointProjectsItOnTheViewDirection) {
    const Scene scene =
        parse(R"("camera": {"look_from": [0, 0, 0], "look_at": [0, 0, -1], "focus_on": [3, 1, -4]})");
    EXPECT_FLOAT_EQ(scene.camera.focusDistance, 4.0f);
}

TEST(CameraFields, BladesRotationAndCameraMotion) {
    const Scene scene =
        parse(R"("camera": {"aperture_radius": 0.1, "aperture_blades": 6, "aperture_rotation": 15,
        "shutter": [0, 0.5], "motion": [{"look_from": [0, 0, 1]}, {"look_from": [1, 0, 1]}]})");
    EXPECT_EQ(scene.camera.apertureBlades, 6);
    EXPECT_FLOAT_EQ(scene.camera.apertureRotationDegrees, 15.0f);
    ASSERT_EQ(scene.camera.motion.size(), 2u);
    EXPECT_EQ(scene.camera.motion[1].lookFrom, Vec3f(1, 0, 1));
    EXPECT_EQ(scene.camera.motion[1].lookAt, scene.camera.lookAt);  // unnamed fields keep the camera's
}

TEST(CameraFields, NegativeAperture) {
    const InputError e = catchInputError([] { parse(R"("camera": {"aperture_radius": -0.1})"); });
    EXPECT_CONTAINS(e.what(), "/camera/aperture_radius");
}

TEST(CameraFields, ZeroFocusDistance) {
    const InputError e = catchInputError([] { parse(R"("camera": {"focus_distance": 0})"); });
    EXPECT_CONTAINS(e.what(), "/camera/focus_distance");
}

TEST(CameraFields, ShutterClosingBeforeItOpens) {
    const InputError e = catchInputError([] { parse(R"("camera": {"shutter": [1, 0.5]})"); });
    EXPECT_CONTAINS(e.what(), "/camera/shutter");
}

TEST(CameraFields, TwoBladesAreNotAnAperture) {
    const InputError e = catchInputError([] { parse(R"("camera": {"aperture_blades": 2})"); });
    EXPECT_CONTAINS(e.what(), "/camera/aperture_blades");
}

TEST(CameraTypes, EachProjectionReadsItsKeys) {
    Scene scene = parse(R"("camera": {"type": "orthographic", "height": 3, "aperture_radius": 0.1,
        "aperture": "pentagon", "focus_distance": 4})");
    EXPECT_EQ(scene.camera.projection, CameraProjection::Orthographic);
    EXPECT_FLOAT_EQ(scene.camera.orthographicHeight, 3.0f);
    EXPECT_EQ(scene.camera.apertureImage.width, 256);
    scene = parse(R"("camera": {"type": "spherical", "mapping": "equal_area", "mirror": true})");
    EXPECT_EQ(scene.camera.sphericalMapping, SphericalMapping::EqualArea);
    EXPECT_TRUE(scene.camera.mirrorColumns);
    scene = parse(R"("camera": {"type": "fisheye", "fov": 220, "mapping": "equisolid"})");
    EXPECT_EQ(scene.camera.fisheyeMapping, FisheyeMapping::Equisolid);
    EXPECT_FLOAT_EQ(scene.camera.verticalFovDegrees, 220.0f);
    scene = parseScene(R"({"camera": {"type": "lens_system", "lens_file": "lenses/dgauss.50mm.dat",
        "aperture_diameter": 8, "film_diagonal": 43.3, "focus_distance": 2, "aperture": "star"}})",
                       std::string(PENUMBRA_SOURCE_DIR) + "/scenes/scene.json");
    EXPECT_EQ(scene.camera.projection, CameraProjection::LensSystem);
    EXPECT_EQ(scene.camera.lensSystem.surfaces.size(), 11u);
    EXPECT_FLOAT_EQ(scene.camera.lensSystem.apertureDiameterMm, 8.0f);
    EXPECT_FLOAT_EQ(scene.camera.lensSystem.filmDiagonalMm, 43.3f);
    EXPECT_FLOAT_EQ(scene.camera.focusDistance, 2.0f);
    EXPECT_FALSE(scene.camera.apertureImage.empty());
}

TEST(CameraTypes, MistakesAreNamedAtTheirKey) {
    auto errorOf = [](const std::string& camera) {
        return std::string(catchInputError([&] { parse(R"("camera": )" + camera); }).what());
    };
    EXPECT_CONTAINS(errorOf(R"({"type": "panoramic"})"), "/camera/type");
    EXPECT_CONTAINS(errorOf(R"({"type": "spherical", "fov": 90})"), "fov");
    EXPECT_CONTAINS(errorOf(R"({"type": "fisheye", "fov": 400})"), "/camera/fov");
    EXPECT_CONTAINS(errorOf(R"({"type": "orthographic", "height": 0})"), "/camera/height");
    EXPECT_CONTAINS(errorOf(R"({"aperture_radius": 0.1, "aperture": "hexagon"})"), "/camera/aperture");
    EXPECT_CONTAINS(errorOf(R"({"aperture_radius": 0.1, "aperture": "missing.png"})"), "missing.png");
    EXPECT_CONTAINS(errorOf(R"({"type": "lens_system"})"), "lens_file");
    const InputError notSquare = catchInputError([] {
        parse(
            R"("camera": {"type": "spherical", "mapping": "equal_area"}, "film": {"resolution": [64, 32]})");
    });
    EXPECT_CONTAINS(notSquare.what(), "/camera/mapping");
    EXPECT_CONTAINS(notSquare.what(), "64x32");
    EXPECT_CONTAINS(errorOf(R"({"type": "lens_system", "lens_file": "none.dat"})"), "/camera/lens_file");
}

TEST(ShapeMotion, TransformKeysAndVertexKeysAreRead) {
    const Scene scene = parse(std::string(kMaterials) + R"(, "camera": {"shutter": [0, 1]}, "shapes": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "grey",
         "motion": {"times": [0, 0.5, 1], "transforms": [{"translate": [0, 0, 0]}, {"rotate": {"axis": [0, 1, 0], "degrees": 90}},
                                                            {"scale": 2, "translate": [1, 0, 0]}]}},
        {"type": "triangle_mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [0, 1, 2], "material": "grey",
         "motion": {"positions": [[[0,0,0],[1,0,0],[0,1,0]], [[0,0,1],[1,0,1],[0,1,1]]]}}])");
    ASSERT_EQ(scene.spheres[0].motion.keys.size(), 3u);
    EXPECT_NEAR(scene.spheres[0].motion.keys[1].rotation.w, std::cos(3.14159265 / 4), 1e-6);
    EXPECT_EQ(scene.spheres[0].motion.keys[2].scale, Vec3f(2, 2, 2));
    ASSERT_EQ(scene.meshes[0].positionKeys.size(), 2u);
    EXPECT_EQ(scene.meshes[0].positionKeys[1][2], Vec3f(0, 1, 1));
}

TEST(ShapeMotion, KeyTimeOutsideTheShutter) {
    const InputError e = catchInputError([] {
        parse(std::string(kMaterials) + R"(, "camera": {"shutter": [0, 1]}, "shapes": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "grey",
             "motion": {"times": [0, 1.5], "transforms": [{"translate": [0, 0, 0]}, {"translate": [1, 0, 0]}]}}])");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/motion/times/1");
    EXPECT_CONTAINS(e.what(), "outside the shutter");
}

TEST(ShapeMotion, UnevenKeyTimes) {
    const InputError e = catchInputError([] {
        parse(std::string(kMaterials) + R"(, "camera": {"shutter": [0, 1]}, "shapes": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "grey",
             "motion": {"times": [0, 0.2, 1], "transforms": [{}, {}, {}]}}])");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/motion/times/1");
    EXPECT_CONTAINS(e.what(), "evenly spaced");
}

TEST(ShapeMotion, MotionNeedsAnOpenShutter) {
    const InputError e = catchInputError([] {
        parse(std::string(kMaterials) + R"(, "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
            "material": "grey", "motion": {"transforms": [{}, {"translate": [1, 0, 0]}]}}])");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/motion");
    EXPECT_CONTAINS(e.what(), "shutter");
}

TEST(ShapeMotion, VertexKeysWithTheWrongCount) {
    const InputError e = catchInputError([] {
        parse(std::string(kMaterials) + R"(, "camera": {"shutter": [0, 1]}, "shapes": [
            {"type": "triangle_mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [0, 1, 2], "material": "grey",
             "motion": {"positions": [[[0,0,0],[1,0,0],[0,1,0]], [[0,0,1],[1,0,1]]]}}])");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/motion/positions/1");
}

TEST(ShapeMotion, MovingLightsAreRefused) {
    const InputError e = catchInputError([] {
        parse(std::string(kMaterials) + R"(, "camera": {"shutter": [0, 1]}, "shapes": [
            {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "grey", "emission": {"radiance": 1},
             "motion": {"transforms": [{}, {"translate": [1, 0, 0]}]}}])");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/motion");
}

TEST(LightFields, ZeroAreaLight) {
    const InputError e = catchInputError([] {
        parse(std::string(kMaterials) + R"(, "shapes": [
            {"type": "triangle_mesh", "positions": [[0,0,0],[1,0,0],[2,0,0]], "indices": [0, 1, 2], "material": "grey",
             "emission": {"radiance": [1, 1, 1]}}])");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/emission");
    EXPECT_CONTAINS(e.what(), "area");
}

TEST(LightFields, DiskIsAFanFacingItsNormal) {
    const Scene scene = parse(std::string(kMaterials) + R"(, "shapes": [
        {"type": "disk", "center": [0, 2, 0], "normal": [0, -1, 0], "radius": 0.5, "segments": 16, "material": "grey"}])");
    const TriangleMesh& disk = scene.meshes[0];
    ASSERT_EQ(disk.triangleCount(), 16u);
    for (size_t t = 0; t < 16; ++t) {
        const Vec3f p0 = disk.positions[disk.indices[3 * t]], p1 = disk.positions[disk.indices[3 * t + 1]],
                    p2 = disk.positions[disk.indices[3 * t + 2]];
        EXPECT_LT(cross(p1 - p0, p2 - p0).y, 0.0f);
        EXPECT_NEAR(length(p1 - Vec3f(0, 2, 0)), 0.5f, 1e-6f);
    }
}

}  // namespace
}  // namespace penumbra
