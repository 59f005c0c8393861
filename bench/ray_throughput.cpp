// penumbra_ray_throughput: how much of a render's time goes to traversal and how much to our own
// code. In one run it
//   (a) renders the scene with the library's render() (the code path of `penumbra render`) and
//       takes its rays per second: camera, bounce and shadow rays over the render time;
//   (b) records a sample of the very rays that render traces and retraces them bare, with
//       rtcIntersect1 / rtcOccluded1 through EmbreeAccelerator (the same Embree scene as the
//       render: built in two levels, the robust flag when the scene is "watertight") and through
//       a plain Embree scene (default flags, medium quality: how Embree's own tutorials build;
//       and once more with the robust flag, to tell its cost apart), on the same threads;
// alternating (a) and (b) --repeat times, and prints the figures as JSON.
//
// Recording: the integrator (renderer/path_integrator.h) is a template over the traversal
// backend, so the recorder is simply a backend that logs each ray and forwards it to
// EmbreeAccelerator: the paths are the render's own (same camera, sampler, integrator), not a
// re-implementation. The recorded sample is every sample of every K-th pixel (K prime, so the
// pixels spread over all columns), kept in render order. A crop of the image is replayed in full
// and its ray counts are checked against render() on the same crop: equal counts show that the
// replay follows the render's paths.
//
//   penumbra_ray_throughput SCENE [--threads N] [--pixel-stride K] [--render-spp N] [--repeat R]
//                                 [--json OUT]
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/embree_accelerator.h"
#include "core/sampling.h"
#include "film/film.h"
#include "renderer/camera_samples.h"
#include "renderer/path_integrator.h"
#include "renderer/prepared_scene.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// One traced ray: what rtcIntersect1 / rtcOccluded1 need (tnear is always 0 in the integrator,
// which the recorder checks).
struct RecordedRay {
    Vec3f origin;
    Vec3f direction;
    float tfar;
    float time;
    uint32_t kind;  // 0 camera, 1 bounce (intersect), 2 shadow (occluded)
};

// A backend for the integrator that logs every ray and answers through EmbreeAccelerator.
struct RecordingAccelerator {
    const EmbreeAccelerator* inner;
    std::vector<RecordedRay>* out;
    mutable bool first = true;  // the next intersect() is the sample's camera ray

    static constexpr std::string_view kName = "recording-embree";
    static constexpr int kPacketSize = 1;
    static constexpr bool kReportsCanonicalHits = EmbreeAccelerator::kReportsCanonicalHits;

    // The paths are those of the render (the triangle a ray leaves skipped); the recording keeps
    // the rays alone, replayed without it.
    bool intersect(const Ray& ray, Hit& hit, TriangleLeft left) const {
        check(ray);
        out->push_back({ray.origin, ray.direction, ray.tfar, ray.time, first ? 0u : 1u});
        first = false;
        return inner->intersect(ray, hit, left);
    }
    bool occluded(const Ray& ray, TriangleLeft left) const {
        check(ray);
        out->push_back({ray.origin, ray.direction, ray.tfar, ray.time, 2u});
        return inner->occluded(ray, left);
    }
    bool occluded(const Ray& ray) const { return occluded(ray, TriangleLeft{}); }
    bool intersect(const Ray& ray, Hit& hit) const { return intersect(ray, hit, TriangleLeft{}); }
    static void check(const Ray& ray) {
        if (ray.tnear != 0.0f) throw std::runtime_error("the recorder assumes tnear = 0");
    }
};

// Replays the render's paths for the given pixels (all samples [0, spp) of each), in render
// order, and returns the rays they trace; one chunk per pixel.
struct Recording {
    std::vector<RecordedRay> rays;
    std::vector<size_t> pixelStart;  // rays of pixel i: [pixelStart[i], pixelStart[i + 1])
    RayCounters counters;
};

Recording recordPaths(const Scene& scene, const EmbreeAccelerator& accel, const std::vector<uint64_t>& pixels,
                      uint32_t spp) {
    const PreparedScene prepared(scene);
    const Camera& camera = prepared.camera();
    const IntegratorContext ctx = prepared.integratorContext();
    const bool sceneMoves = prepared.moves();

    Recording rec;
    RecordingAccelerator recorder{&accel, &rec.rays};
    for (const uint64_t pixelIndex : pixels) {
        rec.pixelStart.push_back(rec.rays.size());
        const int x = int(pixelIndex % uint64_t(scene.film.width));
        const int y = int(pixelIndex / uint64_t(scene.film.width));
        for (uint32_t s = 0; s < spp; ++s) {
            const PixelSample sample(scene.settings.sampler, scene.settings.seed, pixelIndex, s);
            const Ray ray = generateCameraRay(camera, scene.film, sceneMoves, sample, x, y).ray;
            recorder.first = true;
            estimateRadiance(recorder, ctx, ray, sample, rec.counters);
        }
    }
    rec.pixelStart.push_back(rec.rays.size());
    return rec;
}

// ---- bare traversal -------------------------------------------------------------------------

inline RTCRay toRtcRay(const RecordedRay& r) {
    RTCRay ray;
    ray.org_x = r.origin.x;
    ray.org_y = r.origin.y;
    ray.org_z = r.origin.z;
    ray.tnear = 0.0f;
    ray.dir_x = r.direction.x;
    ray.dir_y = r.direction.y;
    ray.dir_z = r.direction.z;
    ray.time = r.time;
    ray.tfar = r.tfar;
    ray.mask = 0xffffffffu;
    ray.id = 0;
    ray.flags = 0;
    return ray;
}

// A plain Embree scene of the scene's triangle meshes, built the way Embree's tutorials build
// theirs (default scene flags, medium build quality).
struct PlainEmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    // robust: with RTC_SCENE_FLAG_ROBUST as EmbreeAccelerator sets it (to tell its cost apart).
    explicit PlainEmbreeScene(const Scene& s, bool robust = false) {
        device = rtcNewDevice(nullptr);
        scene = rtcNewScene(device);
        if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
        for (const TriangleMesh& mesh : s.meshes) {
            if (mesh.triangleCount() == 0) continue;
            if (mesh.motion.moves() || mesh.deforms())
                throw std::runtime_error("the plain Embree scene takes still triangle meshes only");
            RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
            auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
                g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
            std::memcpy(v, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
            auto* i = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
                g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangleCount()));
            std::memcpy(i, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
            rtcCommitGeometry(g);
            rtcAttachGeometry(scene, g);
            rtcReleaseGeometry(g);
        }
        if (!s.spheres.empty()) throw std::runtime_error("the plain Embree scene takes triangle meshes only");
        rtcCommitScene(scene);
    }
    ~PlainEmbreeScene() {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
    bool intersect(const RecordedRay& r) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh;
        rh.ray = toRtcRay(r);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    bool occluded(const RecordedRay& r) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay ray = toRtcRay(r);
        rtcOccluded1(scene, &context, &ray);
        return ray.tfar < 0.0f;
    }
};

struct AcceleratorTracer {
    const EmbreeAccelerator* accel;
    bool intersect(const RecordedRay& r) const {
        Ray ray;
        ray.origin = r.origin;
        ray.direction = r.direction;
        ray.tfar = r.tfar;
        ray.time = r.time;
        Hit hit;
        return accel->intersect(ray, hit);
    }
    bool occluded(const RecordedRay& r) const {
        Ray ray;
        ray.origin = r.origin;
        ray.direction = r.direction;
        ray.tfar = r.tfar;
        ray.time = r.time;
        return accel->occluded(ray);
    }
};

struct TraceResult {
    double seconds = 0;
    uint64_t rays = 0;
    uint64_t hits = 0;  // a checksum that keeps the traversal from being optimized away
    double mraysPerSecond() const { return seconds > 0 ? double(rays) / seconds * 1e-6 : 0.0; }
};

// Traces the recording's rays in chunks of pixels (render order within each chunk) on `threads`
// threads, `passes` times over.
template <typename Tracer>
TraceResult traceAll(const Tracer& tracer, const Recording& rec, int threads, int passes) {
    std::atomic<uint64_t> hits{0};
    tbb::task_arena arena(threads);
    const size_t chunks = rec.pixelStart.size() - 1;
    const auto start = Clock::now();
    for (int p = 0; p < passes; ++p)
        arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<size_t>(0, chunks, 4), [&](const tbb::blocked_range<size_t>& range) {
                    uint64_t local = 0;
                    for (size_t i = rec.pixelStart[range.begin()]; i < rec.pixelStart[range.end()]; ++i) {
                        const RecordedRay& r = rec.rays[i];
                        local += r.kind == 2 ? tracer.occluded(r) : tracer.intersect(r);
                    }
                    hits += local;
                });
        });
    TraceResult result;
    result.seconds = secondsSince(start);
    result.rays = uint64_t(passes) * rec.rays.size();
    result.hits = hits;
    return result;
}

// Random rays, for context (bare Embree on random rays): origins uniform in
// the scene's bounding box, directions uniform on the sphere, unbounded.
Recording randomRays(const Scene& scene, size_t count) {
    Vec3f lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const TriangleMesh& m : scene.meshes)
        for (const Vec3f& p : m.positions)
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[a]);
                hi[a] = std::max(hi[a], p[a]);
            }
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Recording rec;
    rec.rays.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        if (i % 256 == 0) rec.pixelStart.push_back(i);
        Vec3f o;
        for (int a = 0; a < 3; ++a) o[a] = lo[a] + (hi[a] - lo[a]) * u(rng);
        const float z = 1.0f - 2.0f * u(rng), phi = 2.0f * kPi * u(rng),
                    r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        rec.rays.push_back({o, Vec3f{r * std::cos(phi), r * std::sin(phi), z}, INFINITY, 0.0f, 1u});
    }
    rec.pixelStart.push_back(count);
    return rec;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string jsonList(const std::vector<double>& v) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s%.4f", i ? ", " : "", v[i]);
        s += buf;
    }
    return s + "]";
}

int run(int argc, char** argv) {
    std::string scenePath, jsonPath;
    int threads = 2, pixelStride = 61, repeat = 3, renderSpp = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + ": missing value");
            return argv[++i];
        };
        if (a == "--threads")
            threads = std::stoi(next());
        else if (a == "--pixel-stride")
            pixelStride = std::stoi(next());
        else if (a == "--repeat")
            repeat = std::stoi(next());
        else if (a == "--render-spp")
            renderSpp = std::stoi(next());
        else if (a == "--json")
            jsonPath = next();
        else if (a == "--help" || a == "-h") {
            std::printf(
                "usage: penumbra_ray_throughput SCENE [--threads N=2] [--pixel-stride K=61] "
                "[--render-spp N=scene's] [--repeat R=3] [--json OUT]\n");
            return 0;
        } else if (!a.empty() && a[0] == '-')
            throw std::runtime_error("unknown option " + a);
        else
            scenePath = a;
    }
    if (scenePath.empty()) throw std::runtime_error("no scene given (--help for usage)");
    if (threads < 1 || pixelStride < 1 || repeat < 1) throw std::runtime_error("bad option value");

    Scene scene = loadScene(scenePath);
    if (renderSpp > 0) scene.film.samplesPerPixel = renderSpp;
    const uint32_t spp = uint32_t(scene.film.samplesPerPixel);
    const EmbreeAccelerator accel(scene, EmbreeOptions{.robust = scene.settings.watertight});
    const PlainEmbreeScene plain(scene);
    const PlainEmbreeScene plainRobust(scene, true);

    // 1. Check that the replay follows the render: a crop rendered by render() and replayed in full
    //    must trace exactly the same rays, kind by kind.
    const PixelWindow crop{scene.film.width / 2 - 8, scene.film.width / 2 + 8, scene.film.height / 2 - 8,
                           scene.film.height / 2 + 8};
    RayCounters renderCrop;
    {
        RenderOptions options;
        options.threads = threads;
        options.crop = crop;
        Film film(scene.film.width, scene.film.height);
        renderCrop = render(scene, options, film).rays;
    }
    std::vector<uint64_t> cropPixels;
    for (int y = crop.y0; y < crop.y1; ++y)
        for (int x = crop.x0; x < crop.x1; ++x) cropPixels.push_back(uint64_t(y) * scene.film.width + x);
    const Recording cropReplay = recordPaths(scene, accel, cropPixels, spp);
    const bool verified = cropReplay.counters.primary == renderCrop.primary &&
                          cropReplay.counters.extension == renderCrop.extension &&
                          cropReplay.counters.shadow == renderCrop.shadow &&
                          cropReplay.rays.size() == renderCrop.total();

    // 2. The recorded sample: every spp sample of every K-th pixel.
    std::vector<uint64_t> pixels;
    const uint64_t pixelCount = uint64_t(scene.film.width) * scene.film.height;
    for (uint64_t p = 0; p < pixelCount; p += uint64_t(pixelStride)) pixels.push_back(p);
    const auto recordStart = Clock::now();
    const Recording rec = recordPaths(scene, accel, pixels, spp);
    const double recordSeconds = secondsSince(recordStart);
    uint64_t kinds[3] = {0, 0, 0};
    for (const RecordedRay& r : rec.rays) ++kinds[r.kind];
    // Bounce rays per path. The last bin counts paths that trace a bounce ray past their last
    // next-event estimation (at max_depth), which only looks for emitters that BSDF sampling
    // hits; the integrator skips it when nothing can be hit that way (point lights only, black
    // background), as Embree's pathtracer never traces it.
    std::vector<uint64_t> bounceHistogram(size_t(std::max(0, scene.integrator.maxDepth)) + 1, 0);
    for (size_t i = 0; i < rec.rays.size();) {
        size_t bounces = 0, j = i + 1;
        for (; j < rec.rays.size() && rec.rays[j].kind != 0; ++j) bounces += rec.rays[j].kind == 1;
        ++bounceHistogram[std::min(bounces, bounceHistogram.size() - 1)];
        i = j;
    }
    std::string histogram = "[";
    for (size_t i = 0; i < bounceHistogram.size(); ++i)
        histogram += (i ? ", " : "") + std::to_string(bounceHistogram[i]);
    histogram += "]";
    const Recording random = randomRays(scene, size_t(1) << 21);

    // 3. Alternate: full render (a), bare retrace (b), `repeat` times.
    const int passes = std::max(1, int(20'000'000 / std::max<size_t>(1, rec.rays.size())));
    std::vector<double> renderMrays, renderSeconds, bareMrays, plainMrays, plainRobustMrays, randomMrays,
        randomPlainMrays;
    uint64_t renderRays = 0, checksum = 0;
    for (int r = 0; r < repeat; ++r) {
        RenderOptions options;
        options.threads = threads;
        Film film(scene.film.width, scene.film.height);
        const RenderStats stats = render(scene, options, film);
        renderRays = stats.rays.total();
        renderSeconds.push_back(stats.renderSeconds);
        renderMrays.push_back(double(stats.rays.total()) / stats.renderSeconds * 1e-6);

        const TraceResult bare = traceAll(AcceleratorTracer{&accel}, rec, threads, passes);
        const TraceResult barePlain = traceAll(plain, rec, threads, passes);
        const TraceResult barePlainRobust = traceAll(plainRobust, rec, threads, passes);
        plainRobustMrays.push_back(barePlainRobust.mraysPerSecond());
        const TraceResult rnd = traceAll(AcceleratorTracer{&accel}, random, threads, 4);
        const TraceResult rndPlain = traceAll(plain, random, threads, 4);
        bareMrays.push_back(bare.mraysPerSecond());
        plainMrays.push_back(barePlain.mraysPerSecond());
        randomMrays.push_back(rnd.mraysPerSecond());
        randomPlainMrays.push_back(rndPlain.mraysPerSecond());
        checksum += bare.hits + barePlain.hits + barePlainRobust.hits + rnd.hits + rndPlain.hits;
        std::fprintf(
            stderr,
            "repetition %d: render %.2f Mrays/s (%.2f s); bare retrace %.2f Mrays/s (accelerator), %.2f "
            "(plain scene); random rays %.2f / %.2f Mrays/s\n",
            r + 1, renderMrays.back(), stats.renderSeconds, bare.mraysPerSecond(), barePlain.mraysPerSecond(),
            rnd.mraysPerSecond(), rndPlain.mraysPerSecond());
    }

    const double medRender = median(renderMrays), medBare = median(bareMrays), medPlain = median(plainMrays);
    char buf[4096];
    std::snprintf(buf, sizeof buf,
                  "{\n"
                  "  \"scene\": \"%s\",\n"
                  "  \"threads\": %d,\n"
                  "  \"spp\": %u,\n"
                  "  \"replay_verified\": %s,\n"
                  "  \"crop_rays_render\": [%llu, %llu, %llu],\n"
                  "  \"crop_rays_replay\": [%llu, %llu, %llu],\n"
                  "  \"recorded_pixels\": %zu,\n"
                  "  \"pixel_stride\": %d,\n"
                  "  \"recorded_rays\": %zu,\n"
                  "  \"recorded_rays_by_kind\": {\"camera\": %llu, \"bounce\": %llu, \"shadow\": %llu},\n"
                  "  \"bounce_rays_per_path_histogram\": %s,\n"
                  "  \"record_seconds\": %.3f,\n"
                  "  \"retrace_passes\": %d,\n"
                  "  \"render_rays\": %llu,\n"
                  "  \"render_seconds\": %s,\n"
                  "  \"render_mrays_per_s\": %s,\n"
                  "  \"bare_accelerator_mrays_per_s\": %s,\n"
                  "  \"bare_plain_embree_mrays_per_s\": %s,\n"
                  "  \"bare_plain_embree_robust_mrays_per_s\": %s,\n"
                  "  \"random_rays_accelerator_mrays_per_s\": %s,\n"
                  "  \"random_rays_plain_embree_mrays_per_s\": %s,\n"
                  "  \"median_render_mrays_per_s\": %.4f,\n"
                  "  \"median_bare_accelerator_mrays_per_s\": %.4f,\n"
                  "  \"median_bare_plain_embree_mrays_per_s\": %.4f,\n"
                  "  \"render_over_bare_accelerator\": %.4f,\n"
                  "  \"render_over_bare_plain_embree\": %.4f,\n"
                  "  \"checksum\": %llu\n"
                  "}\n",
                  scenePath.c_str(), threads, spp, verified ? "true" : "false",
                  (unsigned long long)renderCrop.primary, (unsigned long long)renderCrop.extension,
                  (unsigned long long)renderCrop.shadow, (unsigned long long)cropReplay.counters.primary,
                  (unsigned long long)cropReplay.counters.extension,
                  (unsigned long long)cropReplay.counters.shadow, pixels.size(), pixelStride, rec.rays.size(),
                  (unsigned long long)kinds[0], (unsigned long long)kinds[1], (unsigned long long)kinds[2],
                  histogram.c_str(), recordSeconds, passes, (unsigned long long)renderRays,
                  jsonList(renderSeconds).c_str(), jsonList(renderMrays).c_str(), jsonList(bareMrays).c_str(),
                  jsonList(plainMrays).c_str(), jsonList(plainRobustMrays).c_str(),
                  jsonList(randomMrays).c_str(), jsonList(randomPlainMrays).c_str(), medRender, medBare,
                  medPlain, medBare > 0 ? medRender / medBare : 0.0,
                  medPlain > 0 ? medRender / medPlain : 0.0, (unsigned long long)checksum);
    std::fputs(buf, stdout);
    if (!jsonPath.empty()) {
        std::ofstream out(jsonPath);
        out << buf;
        if (!out) throw std::runtime_error("cannot write " + jsonPath);
    }
    if (!verified) {
        std::fprintf(
            stderr,
            "penumbra_ray_throughput: the replay does not trace the render's rays (crop counts differ)\n");
        return 3;
    }
    return 0;
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
    try {
        return penumbra::run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_ray_throughput: error: %s\n", e.what());
        return 1;
    }
}
