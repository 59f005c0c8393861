// Our BVH (accel/bvh_accelerator.h) against Embree, in the same run, on the Stanford bunny (69k
// triangles) and the Stanford dragon (871k): build time, trace throughput on coherent camera
// rays, incoherent rays (path bounces and random rays) and shadow segments, and memory per
// triangle. Every benchmark measures both backends on the same input and reports both and their
// ratio (bvh/embree) as counters. Tracing is single-threaded; builds use every core for both.
//
// Meshes are read from $PENUMBRA_DATA_DIR/meshes (default: the CMake cache's PENUMBRA_DATA_DIR).
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "accel/bvh_accelerator.h"
#include "accel/embree_accelerator.h"
#include "scenes/mesh_import.h"
#include "tools/crosscheck.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kImageSize = 512;                // coherent rays: one per pixel, in scanline order
constexpr uint64_t kIncoherentRays = 1 << 17;  // of each incoherent kind

struct RaySet {
    std::vector<Ray> rays;
    std::vector<TriangleLeft> left;  // per ray: the triangle it leaves, named as the integrator names it
    bool segments = false;           // traced with occluded()
};

struct BenchScene {
    Scene scene;
    size_t triangles = 0;
    std::unique_ptr<BvhAccelerator> bvh;
    std::unique_ptr<EmbreeAccelerator> embree;
    RaySet coherent, incoherent, shadow;
};

fs::path dataDir() {
    const char* env = std::getenv("PENUMBRA_DATA_DIR");
    return env ? fs::path(env) : fs::path(PENUMBRA_DATA_DIR);
}

// Loads a mesh once, frames it with a camera, builds both backends and makes the ray sets.
BenchScene* benchScene(const std::string& file) {
    static std::map<std::string, std::unique_ptr<BenchScene>> cache;
    auto& slot = cache[file];
    if (slot) return slot.get();
    const fs::path path = dataDir() / "meshes" / file;
    if (!fs::exists(path)) return nullptr;
    auto b = std::make_unique<BenchScene>();
    b->scene.sourcePath = path;
    b->scene.meshes.push_back(importMesh(path));
    b->triangles = b->scene.meshes[0].triangleCount();
    Vec3f lower = b->scene.meshes[0].positions[0], upper = lower;
    for (const Vec3f& p : b->scene.meshes[0].positions) {
        lower = min(lower, p);
        upper = max(upper, p);
    }
    const Vec3f center = (lower + upper) * 0.5f;
    b->scene.camera.lookAt = center;
    b->scene.camera.lookFrom = center + Vec3f{0.3f, 0.2f, 1.0f} * (1.1f * length(upper - lower));
    b->scene.camera.verticalFovDegrees = 35.0f;
    b->scene.film.width = b->scene.film.height = kImageSize;
    b->bvh = std::make_unique<BvhAccelerator>(b->scene);
    b->embree = std::make_unique<EmbreeAccelerator>(b->scene);

    const Camera camera(b->scene.camera, b->scene.film.width, b->scene.film.height);
    for (int y = 0; y < kImageSize; ++y)
        for (int x = 0; x < kImageSize; ++x)
            b->coherent.rays.push_back(
                camera.generateRay({float(x) + 0.5f, float(y) + 0.5f}, {0.5f, 0.5f}, 0.0f).ray);
    b->coherent.left.resize(b->coherent.rays.size());
    CrosscheckOptions options;
    options.rays = 4 * kIncoherentRays;
    for (const CrosscheckRay& r : generateCrosscheckRays(b->scene, *b->embree, options)) {
        RaySet* set = r.kind == CrosscheckRayKind::Shadow   ? &b->shadow
                      : r.kind == CrosscheckRayKind::Camera ? nullptr
                                                            : &b->incoherent;
        if (!set) continue;
        set->rays.push_back(r.ray);
        // The mesh has no spheres: every surface left is a triangle.
        set->left.push_back(r.leavesSurface ? TriangleLeft{r.sourceGeomId, r.sourcePrimId} : TriangleLeft{});
    }
    b->shadow.segments = true;
    slot = std::move(b);
    return slot.get();
}

// Each ray as the integrator traces it, the triangle it leaves named (`named`), or not.
template <typename Accel>
double traceSeconds(const Accel& accel, const RaySet& set, bool named = true) {
    const auto start = Clock::now();
    const size_t n = set.rays.size();
    if (set.segments) {
        for (size_t i = 0; i < n; ++i)
            benchmark::DoNotOptimize(accel.occluded(set.rays[i], named ? set.left[i] : TriangleLeft{}));
    } else {
        Hit hit;
        for (size_t i = 0; i < n; ++i)
            benchmark::DoNotOptimize(accel.intersect(set.rays[i], hit, named ? set.left[i] : TriangleLeft{}));
    }
    return std::chrono::duration<double>(Clock::now() - start).count();
}

void Trace(benchmark::State& state, const std::string& file, RaySet BenchScene::*which) {
    BenchScene* b = benchScene(file);
    if (!b) return state.SkipWithError(("no mesh " + (dataDir() / "meshes" / file).string()).c_str());
    const RaySet& set = b->*which;
    double ours = 0.0, embree = 0.0, unnamed = 0.0;
    for (auto _ : state) {
        const double o = traceSeconds(*b->bvh, set);
        const double e = traceSeconds(*b->embree, set);
        const double u = traceSeconds(*b->embree, set, false);
        ours += o;
        embree += e;
        unnamed += u;
        state.SetIterationTime(o);
    }
    const double rays = double(set.rays.size()) * double(state.iterations());
    state.counters["rays"] = double(set.rays.size());
    state.counters["bvh_Mrays/s"] = rays / ours * 1e-6;
    state.counters["embree_Mrays/s"] = rays / embree * 1e-6;
    state.counters["bvh/embree"] = embree / ours;  // throughput ratio
    // What skipping the triangle a ray leaves costs Embree (its filter called on each candidate
    // hit): throughput with the triangle named over throughput without.
    state.counters["embree_named/unnamed"] = unnamed / embree;
}

void Build(benchmark::State& state, const std::string& file) {
    BenchScene* b = benchScene(file);
    if (!b) return state.SkipWithError(("no mesh " + (dataDir() / "meshes" / file).string()).c_str());
    double ours = 0.0, embree = 0.0;
    for (auto _ : state) {
        auto start = Clock::now();
        auto bvh = std::make_unique<BvhAccelerator>(b->scene);
        const double o = std::chrono::duration<double>(Clock::now() - start).count();
        start = Clock::now();
        auto e = std::make_unique<EmbreeAccelerator>(b->scene);
        embree += std::chrono::duration<double>(Clock::now() - start).count();
        ours += o;
        state.SetIterationTime(o);
    }
    const double n = double(state.iterations());
    state.counters["triangles"] = double(b->triangles);
    state.counters["bvh_ms"] = ours / n * 1e3;
    state.counters["embree_ms"] = embree / n * 1e3;
    state.counters["bvh/embree"] = ours / embree;  // build time ratio
}

// Embree's own bytes, counted by its memory monitor on a device set up as EmbreeAccelerator sets
// up its own (robust, high build quality, its own copies of the vertex and index buffers).
bool countBytes(void* counter, ssize_t bytes, bool /*post*/) {
    static_cast<std::atomic<int64_t>*>(counter)->fetch_add(bytes);
    return true;
}

double embreeBytes(const TriangleMesh& mesh) {
    std::atomic<int64_t> bytes{0};
    RTCDevice device = rtcNewDevice(nullptr);
    rtcSetDeviceMemoryMonitorFunction(device, countBytes, &bytes);
    const int64_t before = bytes.load();
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    void* vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                             sizeof(Vec3f), mesh.positions.size());
    void* indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(uint32_t), mesh.triangleCount());
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
    std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    const double total = double(bytes.load() - before);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return total;
}

void Memory(benchmark::State& state, const std::string& file) {
    BenchScene* b = benchScene(file);
    if (!b) return state.SkipWithError(("no mesh " + (dataDir() / "meshes" / file).string()).c_str());
    double embree = 0.0;
    for (auto _ : state) embree = embreeBytes(b->scene.meshes[0]);
    const BvhAccelerator::Stats s = b->bvh->stats();
    const double tris = double(b->triangles);
    state.counters["bvh_B/tri"] = double(s.memoryBytes) / tris;
    state.counters["embree_B/tri"] = embree / tris;
    state.counters["bvh/embree"] = double(s.memoryBytes) / embree;
    state.counters["bvh_nodes"] = double(s.nodeCount);  // 4-wide nodes
    state.counters["bvh_leaves"] = double(s.leafCount);
    state.counters["bvh_depth"] = double(s.maxDepth);
    state.counters["bvh_sah"] = double(s.sahCost);
}

void registerAll() {
    for (const std::string file : {"stanford-bunny.obj", "dragon_vrip.ply.gz"}) {
        const std::string name = fs::path(file).stem().stem().string();
        benchmark::RegisterBenchmark(("Build/" + name).c_str(), Build, file)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->MinTime(1.0);
        benchmark::RegisterBenchmark(("TraceCoherent/" + name).c_str(), Trace, file, &BenchScene::coherent)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("TraceIncoherent/" + name).c_str(), Trace, file,
                                     &BenchScene::incoherent)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("TraceShadow/" + name).c_str(), Trace, file, &BenchScene::shadow)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("Memory/" + name).c_str(), Memory, file)->Iterations(1);
    }
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    penumbra::registerAll();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
