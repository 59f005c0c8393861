// The Embree backend: every Embree call of penumbra lives in embree_accelerator.{h,cpp}. The
// per-ray calls are inline here so that the integrator's rays reach Embree without a call of ours
// in between (no copy of the ray through memory, no prologue).
#pragma once

#include <embree3/rtcore.h>
#include <xmmintrin.h>

#include <memory>
#include <vector>

#include "accel/traversal.h"
#include "geometry/scene_geometry.h"

namespace penumbra {

struct EmbreeOptions {
    // RTC_SCENE_FLAG_ROBUST: watertight traversal, no ray slips through a shared edge (see
    // RenderSettings::watertight). Off, traversal is faster (bench/README.md, "Speed tricks").
    bool robust = true;
};

class EmbreeAccelerator {
public:
    explicit EmbreeAccelerator(const SceneGeometry& scene, EmbreeOptions options = {});
    ~EmbreeAccelerator();
    EmbreeAccelerator(const EmbreeAccelerator&) = delete;
    EmbreeAccelerator& operator=(const EmbreeAccelerator&) = delete;

    static constexpr std::string_view kName = "embree";
    // Embree's hits are its own (Plücker-form test): the integrator recomputes them.
    static constexpr bool kReportsCanonicalHits = false;
    bool intersect(const Ray& ray, Hit& hit) const { return intersect(ray, hit, TriangleLeft{}); }
    bool occluded(const Ray& ray) const { return occluded(ray, TriangleLeft{}); }
    // A ray leaving triangle `left` skips it. Embree's triangle test has no error bound on t: it
    // measures the origin's distance from the plane with an error of a few ulps of the triangle's
    // extent from the origin, while the origin's offset (core/ray_offset.h) covers the error of
    // the hit point, a few ulps of its own coordinates. On the Cornell box, 1 in about 400,000
    // rays leaving a surface met its triangle again at every scale (docs/limits.md). Skipping it
    // is exact: a ray leaving a flat triangle cannot meet it again. Embree calls skipTriangleLeft
    // on each candidate hit of such a ray (for intersect, only when its closest hit was that
    // triangle).
    bool intersect(const Ray& ray, Hit& hit, TriangleLeft left) const;
    bool occluded(const Ray& ray, TriangleLeft left) const;

    // Up to kPacketSize coherent rays (a pixel's camera rays) traced together with Embree's packet
    // kernel, which traverses once for all of them; found[i] and hits[i] as intersect() gives them.
    // The packet kernel rounds like itself, not necessarily like the single-ray one, so a ray
    // traced here must always be traced here (the render loop does so for every camera ray).
    static constexpr int kPacketSize = 8;
    void intersectPacket(const Ray* rays, int count, Hit* hits, bool* found) const;

private:
    // What a mesh with a cut-out (geometry/cut_out.h) gives its geometry's filter functions.
    struct CutOut {
        std::shared_ptr<const Texture> alpha;
        std::vector<Vec2f> uvs;
        std::vector<uint32_t> indices;
        uint32_t geomId;  // the mesh's scene id (an instanced geometry's hits name their instance)
    };
    // The cut-out of `mesh` (scene id `geomId`), kept for the backend's life; null when it has none.
    CutOut* cutOutOf(const TriangleMesh& mesh, uint32_t geomId);
    static void filterCutOut(const RTCFilterFunctionNArguments* args);
    // A ribbon's normals (geometry/curves.h), for its geometry's filter: a candidate hit on its flat
    // curve is kept where |v| <= |cos| of the ribbon's normal with the ray.
    struct RibbonNormals {
        std::vector<Vec3f> normals;  // two per segment
    };
    static void filterRibbon(const RTCFilterFunctionNArguments* args);
    // Bilinear patches (geometry/bilinear_patches.h) as a user geometry whose primitives are the
    // patches of one set (its user data, a copy kept for the backend's life), intersected by
    // intersectBilinearPatch, the test our BVH uses, so both find the same hits bit for bit. No
    // filter is called: the only one a patch could meet is skipTriangleLeft, which never names a
    // patch.
    static void boundPatch(const RTCBoundsFunctionArguments* args);
    static void intersectPatch(const RTCIntersectFunctionNArguments* args);
    static void occludedPatch(const RTCOccludedFunctionNArguments* args);

    // The intersection context of a traced ray: Embree's, then the triangle it leaves, for
    // skipTriangleLeft, and the rays as the integrator gave them (indexed by Embree's ray id), for
    // the cut-outs' filter (Embree passes the context it was given to the filters).
    struct TraceContext {
        RTCIntersectContext context;
        TriangleLeft left;
        const Ray* rays;
    };
    static void skipTriangleLeft(const RTCFilterFunctionNArguments* args);
    static void initContext(TraceContext& c, TriangleLeft left, const Ray* rays) {
        rtcInitIntersectContext(&c.context);
        c.left = left;
        c.rays = rays;
        if (!left.isNone()) c.context.filter = skipTriangleLeft;
    }

    // Embree's first two rows of a ray, (org, tnear) and (dir, time), when Embree may trace it:
    // Debian's Embree asserts on rays with NaN or infinite components (and would abort), so such
    // rays are answered without it (they hit nothing), and so are rays without a direction (all
    // three components zero, as for our BVH). The two rows are built from the ray's fields, and
    // one finiteness test covers all eight values (x * 0 is 0 for a finite x, NaN otherwise); tfar
    // may be infinite.
    static bool traceableRows(const Ray& ray, __m128& orgTnear, __m128& dirTime);
    // `ray` in Embree's layout; false (and `out` unset) when Embree must not trace it.
    static bool toTraceableEmbreeRay(const Ray& ray, RTCRay& out);
    // Scene ids from Embree's (geometry/scene_geometry.h): Embree's ids are the scene's but for
    // the moving spheres, numbered after the instances, the curves and the bilinear patches.
    void setIds(unsigned geomId, unsigned primId, Hit& hit) const {
        if (geomId >= movingSphereBase_) [[unlikely]] {
            hit.geomId = sphereGeomId_;
            hit.primId = movingSphereOfGeomId_[geomId - movingSphereBase_];
        } else {
            hit.geomId = geomId;
            hit.primId = primId;
        }
    }

    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    // One per moving object and one per prototype (shared by its instances), released with the
    // backend.
    std::vector<RTCScene> instancedScenes_;
    uint32_t sphereGeomId_ = 0;      // == meshes.size(): all static spheres
    uint32_t movingSphereBase_ = 0;  // Embree's geomId of the first moving sphere, after the patches
    std::vector<uint32_t> movingSphereOfGeomId_;    // geomId - movingSphereBase_ -> sphere index
    std::vector<std::unique_ptr<CutOut>> cutOuts_;  // the filters' user data
    std::vector<std::unique_ptr<RibbonNormals>> ribbons_;
    std::vector<std::unique_ptr<BilinearPatches>> patches_;
};

inline bool EmbreeAccelerator::traceableRows(const Ray& ray, __m128& orgTnear, __m128& dirTime) {
    // Built from the fields, not loaded 16 bytes at a time: the ray was usually just written field
    // by field (bench/README.md, "Store forwarding").
    orgTnear = _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, ray.tnear);
    dirTime = _mm_setr_ps(ray.direction.x, ray.direction.y, ray.direction.z, ray.time);
    const __m128 zero = _mm_setzero_ps();
    const __m128 finite = _mm_and_ps(_mm_cmpeq_ps(_mm_mul_ps(orgTnear, zero), zero),
                                     _mm_cmpeq_ps(_mm_mul_ps(dirTime, zero), zero));
    const bool hasDirection = (_mm_movemask_ps(_mm_cmpneq_ps(dirTime, zero)) & 0x7) != 0;
    return _mm_movemask_ps(finite) == 0xf && hasDirection && ray.tnear >= 0.0f && ray.tfar >= ray.tnear;
}

inline bool EmbreeAccelerator::toTraceableEmbreeRay(const Ray& ray, RTCRay& out) {
    __m128 orgTnear, dirTime;
    if (!traceableRows(ray, orgTnear, dirTime)) return false;
    _mm_store_ps(&out.org_x, orgTnear);
    _mm_store_ps(&out.dir_x, dirTime);
    out.tfar = ray.tfar;
    out.mask = 0xffffffffu;
    out.id = 0;
    out.flags = 0;
    return true;
}

inline bool EmbreeAccelerator::intersect(const Ray& ray, Hit& hit, TriangleLeft left) const {
    RTCRayHit rayHit;
    if (!toTraceableEmbreeRay(ray, rayHit.ray)) return false;
    // Traced without the filter, which Embree would call on every closer candidate hit, at a cost
    // in throughput (bench/README.md, "Speed tricks"): only when the closest hit is the triangle
    // left is the ray traced again, skipping it. The answer is the filtered one either way.
    TraceContext context;
    initContext(context, TriangleLeft{}, &ray);
    rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context.context, &rayHit);
    if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    unsigned instance = rayHit.hit.instID[0];
    if (!left.isNone() && rayHit.hit.primID == left.primId &&
        (instance != RTC_INVALID_GEOMETRY_ID ? instance : rayHit.hit.geomID) == left.geomId) [[unlikely]] {
        initContext(context, left, &ray);
        rayHit.ray.tfar = ray.tfar;
        rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &context.context, &rayHit);
        if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        instance = rayHit.hit.instID[0];
    }
    hit.t = rayHit.ray.tfar;
    hit.u = rayHit.hit.u;
    hit.v = rayHit.hit.v;
    hit.geometricNormal = {rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z};
    setIds(instance != RTC_INVALID_GEOMETRY_ID ? instance : rayHit.hit.geomID, rayHit.hit.primID, hit);
    return true;
}

inline bool EmbreeAccelerator::occluded(const Ray& ray, TriangleLeft left) const {
    RTCRay r;
    if (!toTraceableEmbreeRay(ray, r)) return false;
    TraceContext context;
    initContext(context, left, &ray);
    rtcOccluded1(scene_, &context.context, &r);
    // Embree marks an occluded ray by setting tfar to -infinity.
    return r.tfar < 0.0f;
}

}  // namespace penumbra
static_assert(penumbra::TraversalBackend<penumbra::EmbreeAccelerator>);
