// `penumbra crosscheck`: traces identical ray sets through our BVH and through Embree and explains
// every disagreement.
//
// The rays come in four kinds, each a quarter of the set: camera rays; bounce rays taken from real
// paths (cosine-weighted bounces from the hit points of camera rays); shadow rays from those path
// vertices towards random points on the scene's other surfaces (segments, tested with occluded());
// and rays with random origins in the scene's bounds and random directions. Every ray is a
// function of (seed, kind, index) through core/hash.h, never of a generator's state, and paths
// are traced with Embree, the reference, so the set does not depend on the backend under test.
//
// A ray agrees when both backends miss, or both hit the same primitive (intersect), or both give
// the same answer (occluded). A disagreement is explained when it is one of the expected
// consequences of two different but correct floating-point computations:
//  - edge or vertex: the hit that one backend missed lies within kEdgeTolerance of an edge of its
//    triangle (barycentric coordinate), where the two tests' roundings differ;
//  - tie: two different primitives at the same distance (coplanar or overlapping triangles);
//  - grazing: the ray meets the surface at a glancing angle (|cos| < kGrazingCosine);
//  - range boundary: the hit lies at the ray's tnear or tfar, within the distance tolerance, or
//    within our triangle test's error bound on t of tnear (which that test rejects);
//  - cut-out edge: the hit is on a mesh with a cut-out (geometry/cut_out.h) whose test decides
//    otherwise a barycentric kEdgeTolerance away: where the coverage changes (a texel's or a
//    checker's edge), the two backends' barycentrics, a rounding apart, can see different values;
//  - curve approximation: a curve hit (geometry/curves.h) within the two curve tests' difference:
//    ours is straight within a twentieth of the width (0.1 of the radius in v), Embree's ray-facing
//    quads (16 a segment) within max|P''| / (8 * 16^2) of the curve, so a hit with 1 - |v| below their
//    sum over the radius, or as near a segment's end in u, or two hits on curves within their
//    widths in depth, may be seen by one test and not the other; so may a hit near twice the
//    radius from the origin (both tests see no curve nearer), one within the radius of a
//    segment's end (their depths differ within it), and one of a ray so nearly along the curve
//    (within kCurveAlongDegrees) that Embree's quads look shorter than kCurveForeshortening widths.
//    A ribbon's edge is where |v| is |cos| of its normal with the ray.
// Two are failures: a self-intersection (a ray leaving a surface, a bounce or shadow ray, hits the
// triangle it leaves, or the sphere it leaves within twice its offset: an offset or an error bound
// is too small; but not a ray that points back through its triangle's plane at a glancing angle,
// which is grazing) and anything else, which is unexplained: a bug in one of the backends.
//
// Two distances along a ray agree when the points they give are closer than kDistanceTolerance
// times (the distance travelled + the magnitude of the scene's coordinates): a ray starting a hair
// away from a surface has a tiny t whose rounding error is set by the coordinates, not by t.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "accel/embree_accelerator.h"
#include "accel/traversal.h"
#include "core/ray.h"
#include "scenes/scene.h"

namespace penumbra {

class BvhAccelerator;
class EmbreeAccelerator;

enum class CrosscheckRayKind : uint8_t { Camera, Bounce, Shadow, Random };
inline constexpr int kCrosscheckRayKindCount = 4;
const char* crosscheckRayKindName(CrosscheckRayKind kind);

enum class MismatchKind : uint8_t {
    EdgeOrVertex,
    Tie,
    Grazing,
    RangeBoundary,
    CutOutEdge,
    CurveApproximation,
    SelfIntersection,
    Unexplained
};
inline constexpr int kMismatchKindCount = 8;
const char* mismatchKindName(MismatchKind kind);

inline constexpr float kEdgeTolerance = 1e-5f;      // barycentric coordinate
inline constexpr float kDistanceTolerance = 1e-5f;  // relative, see above
inline constexpr float kGrazingCosine = 1e-3f;      // |cos| between the ray and the surface normal
inline constexpr float kCurveTestChord = 0.1f;  // our curve test's straightness, in radii (geometry/curves.h)
inline constexpr int kEmbreeCurveQuads = 16;    // the tessellation rate the Embree backend sets
inline constexpr float kCurveForeshortening = 4.0f;  // widths, see the curve approximation above
inline constexpr float kCurveAlongDegrees = 15.0f;   // see the curve approximation above

struct CrosscheckRay {
    Ray ray;
    CrosscheckRayKind kind = CrosscheckRayKind::Random;
    uint64_t index = 0;  // within its kind
    // Rays leaving a surface: the primitive left, and how far the origin was moved off the hit
    // point plus that point's error bound (core/ray_offset.h).
    bool leavesSurface = false;
    uint32_t sourceGeomId = 0, sourcePrimId = 0;
    float sourceDistance = 0.0f;
    bool isSegment() const { return kind == CrosscheckRayKind::Shadow; }  // traced with occluded()
};

// What one backend said about one ray. For segments `hit` is the closest hit of intersect() when
// the segment is blocked (to classify it), and hitSomething is the answer of occluded().
struct BackendAnswer {
    bool hitSomething = false;
    bool hasHit = false;
    Hit hit;
};

struct Mismatch {
    CrosscheckRay ray;
    BackendAnswer ours, embree;
    MismatchKind kind = MismatchKind::Unexplained;
};

struct CrosscheckOptions {
    uint64_t rays = 1'000'000;  // in all; each kind gets a quarter
    uint64_t seed = 0;
    bool measureThroughput = true;
    size_t keptMismatches = 1000;  // mismatch records kept (counts are always complete)
};

struct CrosscheckKindStats {
    uint64_t rays = 0;
    uint64_t agreements = 0;
    uint64_t hitMissDisagreements = 0;
    uint64_t primitiveDisagreements = 0;  // both hit, different primitives
};

struct CrosscheckReport {
    std::string scene;
    uint64_t seed = 0;
    uint64_t rayCount = 0;
    uint64_t agreements = 0;
    uint64_t hitMissDisagreements = 0;
    uint64_t primitiveDisagreements = 0;
    std::array<CrosscheckKindStats, kCrosscheckRayKindCount> byKind{};
    // Over the rays where both hit the same primitive: |t_ours - t_embree| / max(t_ours, t_embree),
    // and the distance between the two hit points relative to the scene's coordinate magnitude.
    uint64_t samePrimitiveHits = 0;
    double maxRelativeDistance = 0.0;
    double meanRelativeDistance = 0.0;
    double maxPointDistance = 0.0;
    double meanPointDistance = 0.0;
    std::array<uint64_t, kMismatchKindCount> mismatchesByKind{};
    std::vector<Mismatch> mismatches;  // failures first, at most CrosscheckOptions::keptMismatches
    // Single-thread throughput on the same rays.
    double oursRaysPerSecond = 0.0, embreeRaysPerSecond = 0.0;
    double oursBuildSeconds = 0.0, embreeBuildSeconds = 0.0;

    uint64_t unexplained() const { return mismatchesByKind[size_t(MismatchKind::Unexplained)]; }
    uint64_t selfIntersections() const { return mismatchesByKind[size_t(MismatchKind::SelfIntersection)]; }
    uint64_t failures() const { return unexplained() + selfIntersections(); }
    double agreementRatio() const { return rayCount ? double(agreements) / double(rayCount) : 1.0; }
    // Counting ties as agreements: meshes with overlapping coplanar triangles (scanned meshes
    // often have some) make both answers right.
    double agreementRatioCountingTies() const {
        const uint64_t ties = mismatchesByKind[size_t(MismatchKind::Tie)];
        return rayCount ? double(agreements + ties) / double(rayCount) : 1.0;
    }
};

// The ray set, deterministic in (scene, options.rays, options.seed). Paths for bounce and shadow
// rays are traced with `reference`.
std::vector<CrosscheckRay> generateCrosscheckRays(const Scene& scene, const EmbreeAccelerator& reference,
                                                  const CrosscheckOptions& options);

// Says why two answers differ (they are assumed to differ).
class MismatchClassifier {
public:
    explicit MismatchClassifier(const Scene& scene);
    MismatchKind classify(const CrosscheckRay& ray, const BackendAnswer& ours,
                          const BackendAnswer& embree) const;
    // |a - b| along the ray, as a fraction of the scene's coordinate magnitude.
    double pointDistance(const Ray& ray, float a, float b) const;
    // Whether distances a and b along the ray give the same point within the tolerance.
    bool sameDistance(const Ray& ray, float a, float b) const;

private:
    std::optional<MismatchKind> explainHit(const Ray& ray, const Hit& hit) const;
    bool isSelfIntersection(const CrosscheckRay& ray, const BackendAnswer& answer) const;
    bool crossesItsTriangleAtAGlance(const Ray& ray, const Hit& hit) const;
    bool withinTriangleTestError(const Ray& ray, const Hit& hit) const;
    bool isCutOutEdge(const Ray& ray, const Hit& hit) const;
    // Whether a curve hit lies where the two backends' curve tests may differ (geometry/curves.h):
    // within their approximation of the surface of the silhouette (|v| near 1) or of a segment's
    // end, or, against `other` hit on a curve too, at a depth within their widths.
    bool isCurveApproximation(const Ray& ray, const Hit& hit, const Hit* other = nullptr) const;

    const Scene& scene_;
    float coordinateMagnitude_ = 1.0f;  // largest |coordinate| of the scene's bounds
};

// Compares the two backends on the given rays.
CrosscheckReport compareBackends(const Scene& scene, const BvhAccelerator& ours,
                                 const EmbreeAccelerator& embree, const std::vector<CrosscheckRay>& rays,
                                 const CrosscheckOptions& options);

// Builds both backends, generates the rays and compares.
CrosscheckReport runCrosscheck(const Scene& scene, const CrosscheckOptions& options);

// Human-readable and JSON forms. Mismatching rays are printed with hexadecimal floats (%a), which
// reproduce them bit for bit.
std::string formatCrosscheckText(const CrosscheckReport& report, size_t maxListed = 20);
std::string formatCrosscheckJson(const CrosscheckReport& report, size_t maxListed = 100);

// `penumbra crosscheck SCENE [--patch PATCH]`: 0 when every mismatch is explained and none is a
// self-intersection, kCrosscheckFailed otherwise. `patch` (empty: none) as SceneFileOptions::patch.
// Throws InputError for a bad scene.
inline constexpr int kCrosscheckFailed = 3;
int runCrosscheckCommand(const std::string& scenePath, const std::string& patch,
                         const CrosscheckOptions& options, bool json);

}  // namespace penumbra
