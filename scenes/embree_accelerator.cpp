#include "scenes/embree_accelerator.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace penumbra {

namespace {

[[noreturn]] void throwEmbreeError(RTCDevice device, const char* what) {
    const RTCError code = device ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error code " +
                             std::to_string(int(code)) + ")");
}

void reportEmbreeError(void* /*userPtr*/, RTCError code, const char* message) {
    // Errors are also returned by rtcGetDeviceError; this callback makes them visible at once.
    std::fprintf(stderr, "penumbra: Embree error %d: %s\n", int(code), message ? message : "");
}

void attachTriangleMesh(RTCDevice device, RTCScene scene, const TriangleMesh& mesh, unsigned geomId) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads vertices with 16-byte loads, so its own buffers (which it pads) are used rather
    // than sharing the scene's tightly packed arrays.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangleCount()));
    if (!vertices || !indices) throwEmbreeError(device, "allocating a triangle buffer");
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, geomId);
    rtcReleaseGeometry(geometry);
}

void attachSpheres(RTCDevice device, RTCScene scene, const std::vector<Sphere>& spheres, unsigned geomId) {
    // Real spheres: Embree's sphere points, one primitive per sphere (x, y, z, radius).
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* points = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT4, 4 * sizeof(float),
                                                               spheres.size()));
    if (!points) throwEmbreeError(device, "allocating the sphere buffer");
    for (size_t i = 0; i < spheres.size(); ++i) {
        points[4 * i + 0] = spheres[i].center.x;
        points[4 * i + 1] = spheres[i].center.y;
        points[4 * i + 2] = spheres[i].center.z;
        points[4 * i + 3] = spheres[i].radius;
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene, geometry, geomId);
    rtcReleaseGeometry(geometry);
}

RTCRay toEmbreeRay(const Ray& ray) {
    RTCRay r;
    r.org_x = ray.origin.x;
    r.org_y = ray.origin.y;
    r.org_z = ray.origin.z;
    r.tnear = ray.tnear;
    r.dir_x = ray.direction.x;
    r.dir_y = ray.direction.y;
    r.dir_z = ray.direction.z;
    r.time = ray.time;
    r.tfar = ray.tfar;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    return r;
}

}  // namespace

EmbreeAccelerator::EmbreeAccelerator(const Scene& scene) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throwEmbreeError(nullptr, "creating the device");
    rtcSetDeviceErrorFunction(device_, reportEmbreeError, nullptr);

    scene_ = rtcNewScene(device_);
    // Robust mode avoids the optimizations that let rays slip through shared edges; high build
    // quality because scenes are built once and traced billions of times.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        if (scene.meshes[i].triangleCount() > 0) attachTriangleMesh(device_, scene_, scene.meshes[i], unsigned(i));
    if (!scene.spheres.empty()) attachSpheres(device_, scene_, scene.spheres, unsigned(scene.meshes.size()));
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throwEmbreeError(device_, "building the scene");
}

EmbreeAccelerator::~EmbreeAccelerator() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

bool EmbreeAccelerator::intersect(const Ray& ray, Hit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayHit;
    rayHit.ray = toEmbreeRay(ray);
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rayHit.ray.tfar;
    hit.u = rayHit.hit.u;
    hit.v = rayHit.hit.v;
    hit.geometricNormal = {rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z};
    hit.geomId = rayHit.hit.geomID;
    hit.primId = rayHit.hit.primID;
    return true;
}

bool EmbreeAccelerator::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r = toEmbreeRay(ray);
    rtcOccluded1(scene_, &context, &r);
    // Embree marks an occluded ray by setting tfar to -infinity.
    return r.tfar < 0.0f;
}

}  // namespace penumbra
