#include "accel/embree_accelerator.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "geometry/cut_out.h"

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

// Embree reads vertices with 16-byte loads, so its own buffers (which it pads) are used rather
// than sharing the scene's tightly packed arrays.
void setVertices(RTCDevice device, RTCGeometry geometry, unsigned slot, const std::vector<Vec3f>& positions) {
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, slot, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
    if (!vertices) throwEmbreeError(device, "allocating a vertex buffer");
    std::memcpy(vertices, positions.data(), positions.size() * sizeof(Vec3f));
}

// A triangle geometry; a deforming mesh gets one vertex buffer per time step, which Embree
// interpolates linearly, as geometry/surface_interaction.h does. With a `filter`, it is called with
// `userData` on every candidate hit, for intersect and occluded (a cut-out's test).
RTCGeometry newTriangleGeometry(RTCDevice device, const TriangleMesh& mesh,
                                RTCFilterFunctionN filter = nullptr, void* userData = nullptr) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (mesh.deforms()) {
        rtcSetGeometryTimeStepCount(geometry, unsigned(mesh.positionKeys.size()));
        for (size_t k = 0; k < mesh.positionKeys.size(); ++k)
            setVertices(device, geometry, unsigned(k), mesh.positionKeys[k]);
    } else {
        setVertices(device, geometry, 0, mesh.positions);
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangleCount()));
    if (!indices) throwEmbreeError(device, "allocating an index buffer");
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    if (filter) {
        rtcSetGeometryUserData(geometry, userData);
        rtcSetGeometryIntersectFilterFunction(geometry, filter);
        rtcSetGeometryOccludedFilterFunction(geometry, filter);
    }
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);  // its own BVH, in a two-level scene
    rtcCommitGeometry(geometry);
    return geometry;
}

// Real spheres: Embree's sphere points, one primitive per sphere (x, y, z, radius).
RTCGeometry newSphereGeometry(RTCDevice device, const std::vector<const Sphere*>& spheres) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* points = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
    if (!points) throwEmbreeError(device, "allocating the sphere buffer");
    for (size_t i = 0; i < spheres.size(); ++i) {
        points[4 * i + 0] = spheres[i]->center.x;
        points[4 * i + 1] = spheres[i]->center.y;
        points[4 * i + 2] = spheres[i]->center.z;
        points[4 * i + 3] = spheres[i]->radius;
    }
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);  // as a triangle geometry's
    rtcCommitGeometry(geometry);
    return geometry;
}

// Our curve segments (geometry/curves.h) as Embree's flat (ray-facing) Bezier curves, four control
// points (x, y, z, radius) each. Embree tessellates a flat curve's segment into ray-facing quads;
// at 16 a segment rather than its default 4, its silhouettes lie closer to our test's
// (tools/crosscheck.h, "curve edge"). A ribbon's filter narrows it by its normal.
RTCGeometry newCurveGeometry(RTCDevice device, const Curves& curves, RTCFilterFunctionN filter,
                             void* userData) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE);
    const size_t segments = curves.segmentCount();
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 4 * segments));
    if (!vertices) throwEmbreeError(device, "allocating a curve vertex buffer");
    for (size_t i = 0; i < 4 * segments; ++i) {
        vertices[4 * i + 0] = curves.points[i].x;
        vertices[4 * i + 1] = curves.points[i].y;
        vertices[4 * i + 2] = curves.points[i].z;
        vertices[4 * i + 3] = curves.radii[i];
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), segments));
    if (!indices) throwEmbreeError(device, "allocating a curve index buffer");
    for (size_t j = 0; j < segments; ++j) indices[j] = unsigned(4 * j);
    rtcSetGeometryTessellationRate(geometry, 16.0f);
    if (filter) {
        rtcSetGeometryUserData(geometry, userData);
        rtcSetGeometryIntersectFilterFunction(geometry, filter);
        rtcSetGeometryOccludedFilterFunction(geometry, filter);
    }
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(geometry);
    return geometry;
}

// A scene that holds one geometry (an instanced prototype, a moving object): one BVH over its
// primitives, of high build quality because scenes are built once and traced billions of times.
// Robust mode avoids the optimizations that let rays slip through shared edges. Every scene,
// instanced ones too, calls the intersection context's filter (the triangle a ray leaves is skipped).
RTCScene newScene(RTCDevice device, const EmbreeOptions& options) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTCSceneFlags((options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                          RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    return scene;
}

// The scene's top level, built in two levels: a BVH for each geometry (at the geometry's own
// build quality, high for ours: Embree's SAH builder), then one over the geometries (Embree builds
// a scene of low build quality so: rtcSetSceneBuildQuality's documentation). One BVH over every
// triangle of the scene groups triangles by their centroids, not by object. In two levels an
// object of up to four triangles is one leaf (one SIMD test; a wall's two triangles, a flat box),
// a larger one keeps its own BVH, and the top level opens those BVHs where objects overlap
// (Embree's BVHNBuilderTwoLevel). Less render time on scenes of a few objects, the same on large
// meshes (bench/README.md, "Speed tricks").
RTCScene newTwoLevelScene(RTCDevice device, const EmbreeOptions& options) {
    RTCScene scene = newScene(device, options);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    return scene;
}

void attach(RTCScene scene, RTCGeometry geometry, unsigned geomId) {
    rtcAttachGeometryByID(scene, geometry, geomId);
    rtcReleaseGeometry(geometry);
}

// A moving object: its geometry alone in a scene of its own, placed by a motion instance with
// one quaternion decomposition per key (scale, then slerped rotation, then translation).
RTCGeometry newMotionInstance(RTCDevice device, RTCScene child, const MotionTransform& motion) {
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, child);
    rtcSetGeometryTimeStepCount(instance, unsigned(motion.keys.size()));
    for (size_t k = 0; k < motion.keys.size(); ++k) {
        const TransformKey& key = motion.keys[k];
        RTCQuaternionDecomposition decomposition;
        rtcInitQuaternionDecomposition(&decomposition);
        rtcQuaternionDecompositionSetScale(&decomposition, key.scale.x, key.scale.y, key.scale.z);
        rtcQuaternionDecompositionSetQuaternion(&decomposition, key.rotation.w, key.rotation.v.x,
                                                key.rotation.v.y, key.rotation.v.z);
        rtcQuaternionDecompositionSetTranslation(&decomposition, key.translation.x, key.translation.y,
                                                 key.translation.z);
        rtcSetGeometryTransformQuaternion(instance, unsigned(k), &decomposition);
    }
    rtcCommitGeometry(instance);
    return instance;
}

// A still instance: the prototype's scene placed by one affine transform.
RTCGeometry newStillInstance(RTCDevice device, RTCScene child, const Transform& toWorld) {
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, child);
    float rows[12];
    for (int row = 0; row < 3; ++row)
        for (int column = 0; column < 4; ++column) rows[4 * row + column] = toWorld.matrix().m[row][column];
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, rows);
    rtcCommitGeometry(instance);
    return instance;
}

}  // namespace

EmbreeAccelerator::EmbreeAccelerator(const SceneGeometry& scene, EmbreeOptions options) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throwEmbreeError(nullptr, "creating the device");
    rtcSetDeviceErrorFunction(device_, reportEmbreeError, nullptr);

    scene_ = newTwoLevelScene(device_, options);
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        const TriangleMesh& mesh = scene.meshes[i];
        if (mesh.triangleCount() == 0) continue;
        CutOut* cutOut = cutOutOf(mesh, uint32_t(i));
        const RTCFilterFunctionN filter = cutOut ? filterCutOut : nullptr;
        if (!mesh.motion.moves()) {
            attach(scene_, newTriangleGeometry(device_, mesh, filter, cutOut), unsigned(i));
            continue;
        }
        RTCScene child = newScene(device_, options);
        instancedScenes_.push_back(child);
        attach(child, newTriangleGeometry(device_, mesh, filter, cutOut), 0);
        rtcCommitScene(child);
        attach(scene_, newMotionInstance(device_, child, mesh.motion), unsigned(i));
    }
    sphereGeomId_ = scene.sphereGeomId();
    // Instances: each prototype is a scene of its own, built once, that all its instances place
    // (Embree's instanced_geometry tutorial). Hits report the instance's geomId in instID[0] and
    // the prototype's triangle in primID.
    std::vector<RTCScene> prototypeScenes(scene.prototypes.size(), nullptr);
    for (size_t p = 0; p < scene.prototypes.size(); ++p) {
        if (scene.prototypes[p].triangleCount() == 0) continue;
        RTCScene child = newScene(device_, options);
        instancedScenes_.push_back(child);
        CutOut* cutOut = cutOutOf(scene.prototypes[p], 0);
        attach(child,
               newTriangleGeometry(device_, scene.prototypes[p], cutOut ? filterCutOut : nullptr, cutOut), 0);
        rtcCommitScene(child);
        prototypeScenes[p] = child;
    }
    for (size_t k = 0; k < scene.instances.size(); ++k) {
        const MeshInstance& instance = scene.instances[k];
        RTCScene child = prototypeScenes[instance.prototype];
        if (!child) continue;
        attach(scene_,
               instance.moves() ? newMotionInstance(device_, child, instance.motion)
                                : newStillInstance(device_, child, instance.placement),
               scene.instanceGeomId(k));
    }
    for (size_t c = 0; c < scene.curves.size(); ++c) {
        const Curves& curves = scene.curves[c];
        if (curves.segmentCount() == 0) continue;
        RibbonNormals* ribbon = nullptr;
        if (curves.type == CurveType::Ribbon) {
            ribbons_.push_back(std::make_unique<RibbonNormals>(RibbonNormals{curves.normals}));
            ribbon = ribbons_.back().get();
        }
        attach(scene_, newCurveGeometry(device_, curves, ribbon ? filterRibbon : nullptr, ribbon),
               scene.curvesGeomId(c));
    }
    for (size_t b = 0; b < scene.patches.size(); ++b) {
        if (scene.patches[b].patchCount() == 0) continue;
        patches_.push_back(std::make_unique<BilinearPatches>(scene.patches[b]));
        RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geometry, unsigned(scene.patches[b].patchCount()));
        rtcSetGeometryUserData(geometry, patches_.back().get());
        rtcSetGeometryBoundsFunction(geometry, boundPatch, nullptr);
        rtcSetGeometryIntersectFunction(geometry, intersectPatch);
        rtcSetGeometryOccludedFunction(geometry, occludedPatch);
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(geometry);
        attach(scene_, geometry, scene.patchesGeomId(b));
    }
    movingSphereBase_ = scene.patchesGeomId(scene.patches.size());
    std::vector<const Sphere*> staticSpheres;
    for (const Sphere& sphere : scene.spheres)
        if (!sphere.motion.moves()) staticSpheres.push_back(&sphere);
    // Still spheres share one geometry whose primitive ids are the sphere indices. Once any sphere
    // moves, every sphere gets an instance of its own (still ones a fixed placement), and the
    // instance ids map back to sphere indices.
    if (staticSpheres.size() == scene.spheres.size()) {
        if (!staticSpheres.empty()) attach(scene_, newSphereGeometry(device_, staticSpheres), sphereGeomId_);
    } else {
        for (size_t s = 0; s < scene.spheres.size(); ++s) {
            const Sphere& sphere = scene.spheres[s];
            RTCScene child = newScene(device_, options);
            instancedScenes_.push_back(child);
            attach(child, newSphereGeometry(device_, {&sphere}), 0);
            rtcCommitScene(child);
            MotionTransform placement = sphere.motion;
            if (!placement.moves()) placement.keys = {TransformKey{}, TransformKey{}};  // identity, twice
            const unsigned geomId = movingSphereBase_ + unsigned(movingSphereOfGeomId_.size());
            attach(scene_, newMotionInstance(device_, child, placement), geomId);
            movingSphereOfGeomId_.push_back(uint32_t(s));
        }
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throwEmbreeError(device_, "building the scene");
}

EmbreeAccelerator::~EmbreeAccelerator() {
    if (scene_) rtcReleaseScene(scene_);
    for (RTCScene child : instancedScenes_) rtcReleaseScene(child);
    if (device_) rtcReleaseDevice(device_);
}

EmbreeAccelerator::CutOut* EmbreeAccelerator::cutOutOf(const TriangleMesh& mesh, uint32_t geomId) {
    if (!mesh.alpha) return nullptr;
    cutOuts_.push_back(std::make_unique<CutOut>(CutOut{mesh.alpha, mesh.uvs, mesh.indices, geomId}));
    return cutOuts_.back().get();
}

// A candidate hit on a mesh with a cut-out is refused when keepsCutOutHit says so, with the number
// of the integrator's ray (the context's) and the hit's scene ids: an instanced geometry's hit is
// named by its instance, as our BVH names it.
void EmbreeAccelerator::filterCutOut(const RTCFilterFunctionNArguments* args) {
    const auto& cutOut = *static_cast<const CutOut*>(args->geometryUserPtr);
    const Ray* rays = reinterpret_cast<const TraceContext*>(args->context)->rays;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        const unsigned primId = RTCHitN_primID(args->hit, args->N, i);
        const unsigned instance = RTCHitN_instID(args->hit, args->N, i, 0);
        const uint32_t geomId = instance != RTC_INVALID_GEOMETRY_ID ? instance : cutOut.geomId;
        const float b1 = RTCHitN_u(args->hit, args->N, i), b2 = RTCHitN_v(args->hit, args->N, i);
        const float alpha =
            cutOutCoverage(*cutOut.alpha, meshUvAt(cutOut.uvs, &cutOut.indices[3 * primId], b1, b2));
        const Ray& ray = rays[RTCRayN_id(args->ray, args->N, i)];
        if (!keepsCutOutHit(alpha, cutOutRayHash(ray), geomId, primId)) args->valid[i] = 0;
    }
}

void EmbreeAccelerator::filterRibbon(const RTCFilterFunctionNArguments* args) {
    const auto& ribbon = *static_cast<const RibbonNormals*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        const unsigned segment = RTCHitN_primID(args->hit, args->N, i);
        const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
        const Vec3f direction{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                              RTCRayN_dir_z(args->ray, args->N, i)};
        const Vec3f normal =
            curve::ribbonNormal(ribbon.normals[2 * segment], ribbon.normals[2 * segment + 1], u);
        if (!(std::abs(v) <= std::abs(dot(normal, normalize(direction))))) args->valid[i] = 0;
    }
}

// The box of a patch's corners (which hold the patch), padded by a few ulps of its largest
// coordinate for the rounding of the test's points. A patch with a corner that is not finite gets an
// empty box and is never tested (as our BVH leaves it out).
void EmbreeAccelerator::boundPatch(const RTCBoundsFunctionArguments* args) {
    const auto& patches = *static_cast<const BilinearPatches*>(args->geometryUserPtr);
    const std::array<Vec3f, 4> p = patches.cornerPositions(args->primID);
    Vec3f lower = p[0], upper = p[0];
    bool finite = true;
    for (const Vec3f& corner : p) {
        finite = finite && isFinite(corner);
        lower = min(lower, corner);
        upper = max(upper, corner);
    }
    const float pad = std::max(maxComponent(abs(lower)), maxComponent(abs(upper))) * 4e-7f;
    RTCBounds& box = *args->bounds_o;
    if (!finite) {
        box = {1.0f, 1.0f, 1.0f, 0.0f, -1.0f, -1.0f, -1.0f, 0.0f};
        return;
    }
    box = {lower.x - pad, lower.y - pad, lower.z - pad, 0.0f,
           upper.x + pad, upper.y + pad, upper.z + pad, 0.0f};
}

namespace {

// Ray i of Embree's packet of n, and whether intersectBilinearPatch meets patch `p` on it.
bool hitsPatch(const std::array<Vec3f, 4>& p, RTCRayN* rays, unsigned n, unsigned i, BilinearPatchHit& hit) {
    const Vec3f origin{RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i), RTCRayN_org_z(rays, n, i)};
    const Vec3f direction{RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i)};
    return intersectBilinearPatch(p.data(), origin, direction, RTCRayN_tnear(rays, n, i),
                                  RTCRayN_tfar(rays, n, i), hit);
}

}  // namespace

void EmbreeAccelerator::intersectPatch(const RTCIntersectFunctionNArguments* args) {
    const auto& patches = *static_cast<const BilinearPatches*>(args->geometryUserPtr);
    const std::array<Vec3f, 4> p = patches.cornerPositions(args->primID);
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        BilinearPatchHit hit;
        if (args->valid[i] == 0 || !hitsPatch(p, rays, args->N, i, hit)) continue;
        const Vec3f normal = cross(bilinear::dpdu(p.data(), hit.v), bilinear::dpdv(p.data(), hit.u));
        RTCRayN_tfar(rays, args->N, i) = hit.t;
        RTCHitN_u(hits, args->N, i) = hit.u;
        RTCHitN_v(hits, args->N, i) = hit.v;
        RTCHitN_Ng_x(hits, args->N, i) = normal.x;
        RTCHitN_Ng_y(hits, args->N, i) = normal.y;
        RTCHitN_Ng_z(hits, args->N, i) = normal.z;
        RTCHitN_primID(hits, args->N, i) = args->primID;
        RTCHitN_geomID(hits, args->N, i) = args->geomID;
        RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
    }
}

void EmbreeAccelerator::occludedPatch(const RTCOccludedFunctionNArguments* args) {
    const auto& patches = *static_cast<const BilinearPatches*>(args->geometryUserPtr);
    const std::array<Vec3f, 4> p = patches.cornerPositions(args->primID);
    for (unsigned i = 0; i < args->N; ++i) {
        BilinearPatchHit hit;
        if (args->valid[i] == 0 || !hitsPatch(p, args->ray, args->N, i, hit)) continue;
        RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    }
}

// A candidate hit on the triangle the ray leaves is refused. Hits on a moving mesh or an instance
// name it by instID[0] (its scene id, as setIds maps it); still meshes by geomID.
void EmbreeAccelerator::skipTriangleLeft(const RTCFilterFunctionNArguments* args) {
    const TriangleLeft left = reinterpret_cast<const TraceContext*>(args->context)->left;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        const unsigned instance = RTCHitN_instID(args->hit, args->N, i, 0);
        const unsigned geomId =
            instance != RTC_INVALID_GEOMETRY_ID ? instance : RTCHitN_geomID(args->hit, args->N, i);
        if (geomId == left.geomId && RTCHitN_primID(args->hit, args->N, i) == left.primId) args->valid[i] = 0;
    }
}

void EmbreeAccelerator::intersectPacket(const Ray* rays, int count, Hit* hits, bool* found) const {
    alignas(32) int valid[kPacketSize];
    RTCRayHit8 packet;
    for (int i = 0; i < kPacketSize; ++i) {
        __m128 orgTnear, dirTime;
        const bool traced = i < count && traceableRows(rays[i], orgTnear, dirTime);
        valid[i] = traced ? -1 : 0;
        const Ray& ray = rays[traced ? i : 0];
        packet.ray.org_x[i] = ray.origin.x;
        packet.ray.org_y[i] = ray.origin.y;
        packet.ray.org_z[i] = ray.origin.z;
        packet.ray.dir_x[i] = ray.direction.x;
        packet.ray.dir_y[i] = ray.direction.y;
        packet.ray.dir_z[i] = ray.direction.z;
        packet.ray.tnear[i] = ray.tnear;
        packet.ray.tfar[i] = ray.tfar;
        packet.ray.time[i] = ray.time;
        packet.ray.mask[i] = 0xffffffffu;
        packet.ray.id[i] = unsigned(i);
        packet.ray.flags[i] = 0;
        packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    TraceContext context;
    initContext(context, TriangleLeft{}, rays);
    context.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect8(valid, scene_, &context.context, &packet);
    for (int i = 0; i < count; ++i) {
        found[i] = valid[i] && packet.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        if (!found[i]) continue;
        Hit& hit = hits[i];
        hit.t = packet.ray.tfar[i];
        hit.u = packet.hit.u[i];
        hit.v = packet.hit.v[i];
        hit.geometricNormal = {packet.hit.Ng_x[i], packet.hit.Ng_y[i], packet.hit.Ng_z[i]};
        const unsigned instance = packet.hit.instID[0][i];
        setIds(instance != RTC_INVALID_GEOMETRY_ID ? instance : packet.hit.geomID[i], packet.hit.primID[i],
               hit);
    }
}

}  // namespace penumbra
