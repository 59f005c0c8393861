// Merge throughput (docs/scale-out.md): how fast `penumbra merge` adds full-frame parts. Renders
// one real film of an example scene at one sample per pixel, writes it PARTS times as the parts
// [i, i+1) of a PARTS-sample render (the same bytes a real one-sample part has; only the sample
// range in the metadata differs), then merges them one at a time as `merge` does (FilmMerger:
// read a part, add it) and writes the result. In the same run, the peer: reading the same files'
// bytes and nothing else. Prints bytes per pixel on disk, and parts x pixels per second.
//
//   penumbra_merge_throughput SCENE [--parts 64] [--res 1920x1080] [--dir DIR (default
//   $TMPDIR/penumbra-merge-bench)] [--keep 1]
//
// Each phase is timed on the wall clock and in CPU seconds of the process (on a busy shared
// machine the CPU seconds are the figure to trust). With --keep 1 the part files stay in DIR and
// a later run reuses them (their writing is then not timed).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "film/film_exr.h"
#include "film/film_merge.h"
#include "renderer/render_job.h"
#include "scenes/scene_loader.h"

using namespace penumbra;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// User and system CPU seconds of the process so far (every thread).
double cpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE [--parts N] [--res WxH] [--dir DIR]\n", argv[0]);
        return 2;
    }
    try {
        Scene scene = loadScene(argv[1]);
        int parts = 64;
        scene.film.width = 1920;
        scene.film.height = 1080;
        fs::path dir = fs::temp_directory_path() / "penumbra-merge-bench";  // $TMPDIR, else /tmp
        bool keep = false;
        for (int i = 2; i + 1 < argc; i += 2) {
            const std::string option = argv[i], value = argv[i + 1];
            if (option == "--parts")
                parts = std::stoi(value);
            else if (option == "--res")
                std::sscanf(value.c_str(), "%dx%d", &scene.film.width, &scene.film.height);
            else if (option == "--dir")
                dir = value;
            else if (option == "--keep")
                keep = value == "1";
            else
                throw InputError("unknown option " + option);
        }
        fs::create_directories(dir);
        const double pixels = double(scene.film.width) * scene.film.height;

        RenderOptions options;
        options.firstSample = 0;
        options.endSample = 1;
        RenderJob job(scene, SceneSource::of(argv[1], scene), options);
        const RenderStats stats = job.run();

        std::vector<fs::path> files;
        auto start = Clock::now();
        double cpu = cpuSeconds();
        int written = 0;
        for (int i = 0; i < parts; ++i) {
            RenderMetadata m = job.metadata();
            m.firstSample = uint32_t(i);
            m.endSample = uint32_t(i + 1);
            files.push_back(dir / ("part-" + std::to_string(i) + ".exr"));
            if (keep && fs::exists(files.back())) continue;
            writeExr(job.film(), m, files.back());
            ++written;
        }
        const double writeSeconds = secondsSince(start), writeCpu = cpuSeconds() - cpu;
        uint64_t bytes = 0;
        for (const fs::path& f : files) bytes += fs::file_size(f);

        // The peer: the files' bytes read, nothing done with them (mostly from the page cache).
        start = Clock::now();
        cpu = cpuSeconds();
        std::vector<char> buffer(size_t(1) << 24);
        for (const fs::path& f : files) {
            std::ifstream in(f, std::ios::binary);
            while (in.read(buffer.data(), std::streamsize(buffer.size())) || in.gcount() > 0) {
            }
        }
        const double readBytesSeconds = secondsSince(start), readBytesCpu = cpuSeconds() - cpu;

        double readSeconds = 0, addSeconds = 0, readCpu = 0, addCpu = 0;
        FilmMerger merger;
        for (const fs::path& f : files) {
            start = Clock::now();
            cpu = cpuSeconds();
            FilmFile part = readFilmExr(f);
            readSeconds += secondsSince(start);
            readCpu += cpuSeconds() - cpu;
            start = Clock::now();
            cpu = cpuSeconds();
            merger.add(std::move(part), f.string());
            addSeconds += secondsSince(start);
            addCpu += cpuSeconds() - cpu;
        }
        start = Clock::now();
        MergeResult merged = merger.finish();
        const double finishSeconds = secondsSince(start);
        start = Clock::now();
        writeExr(merged.merged.film, merged.merged.metadata, dir / "merged.exr");
        const double mergedWriteSeconds = secondsSince(start);
        const uint64_t mergedBytes = fs::file_size(dir / "merged.exr");
        if (merged.merged.film.at(0, 0).sampleCount != uint32_t(parts) ||
            merged.merged.metadata.endSample != uint32_t(parts))
            throw InputError("the merged film does not hold every part's sample");
        if (!keep)
            for (const fs::path& f : files) fs::remove(f);
        fs::remove(dir / "merged.exr");

        const double mergeSeconds = readSeconds + addSeconds;
        const double partPixels = parts * pixels;
        std::printf("%s at %dx%d, %d parts of one sample each\n", argv[1], scene.film.width,
                    scene.film.height, parts);
        std::printf("render of one part: %.2f s (%.2f M samples/s)\n", stats.renderSeconds,
                    pixels / stats.renderSeconds * 1e-6);
        std::printf("part on disk: %.1f MB, %.1f bytes/pixel (merged film: %.1f bytes/pixel)\n",
                    double(bytes) / parts * 1e-6, double(bytes) / parts / pixels,
                    double(mergedBytes) / pixels);
        if (written > 0)
            std::printf("writing a part: %.2f s wall, %.2f s CPU\n", writeSeconds / written,
                        writeCpu / written);
        std::printf(
            "| phase | wall s | CPU s | M parts x pixels / wall s | M parts x pixels / CPU s | MB / wall s "
            "|\n|---|---|---|---|---|---|\n");
        auto row = [&](const char* what, double wall, double cpuTime) {
            std::printf("| %s | %.2f | %.2f | %.1f | %.1f | %.0f |\n", what, wall, cpuTime,
                        partPixels / wall * 1e-6, partPixels / std::max(cpuTime, 1e-9) * 1e-6,
                        double(bytes) / wall * 1e-6);
        };
        row("peer: read the bytes", readBytesSeconds, readBytesCpu);
        row("merge: read films", readSeconds, readCpu);
        row("merge: add films", addSeconds, addCpu);
        row("merge: read + add", mergeSeconds, readCpu + addCpu);
        std::printf("checks after the last part: %.2f s; writing the merged film: %.2f s\n", finishSeconds,
                    mergedWriteSeconds);
        std::printf("merge / peer, wall time: %.1f\n", mergeSeconds / readBytesSeconds);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_merge_throughput: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
