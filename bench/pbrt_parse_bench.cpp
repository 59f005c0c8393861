// Reading pbrt-v4 scenes (formats/pbrt): parse speed in MB/s for a 1M-triangle ASCII
// "trianglemesh" and for a 1M-triangle binary PLY named by a "plymesh", and the time to load the
// 871k-triangle Stanford dragon from a .pbrt file against Embree's build of the same mesh, in the
// same run (the peer: loading must not be the slower half of getting a scene ready).
//
//   penumbra_pbrt_parse_bench [REPEATS]     (best of REPEATS, default 3)
//
// The dragon is read from $PENUMBRA_DATA_DIR/meshes (default: the CMake cache's PENUMBRA_DATA_DIR).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "accel/embree_accelerator.h"
#include "formats/pbrt/parser.h"
#include "formats/pbrt/pbrt_reader.h"
#include "formats/scene_file.h"

namespace fs = std::filesystem;
using namespace penumbra;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kGrid = 708;  // vertices a side: 2 * 707^2 = 999,698 triangles

double bestSeconds(int repeats, const std::function<void()>& run) {
    double best = 1e30;
    for (int i = 0; i < repeats; ++i) {
        const auto start = Clock::now();
        run();
        best = std::min(best, std::chrono::duration<double>(Clock::now() - start).count());
    }
    return best;
}

// A wavy grid, so that the numbers have the digits of real meshes.
float heightAt(int x, int y) { return 0.1f * std::sin(0.05f * float(x)) * std::cos(0.07f * float(y)); }

void writeAsciiMesh(const fs::path& file) {
    std::string text = "WorldBegin\nShape \"trianglemesh\"\n  \"point3 P\" [\n";
    for (int y = 0; y < kGrid; ++y)
        for (int x = 0; x < kGrid; ++x)
            text += fmt::format("{} {} {}\n", float(x) / kGrid, float(y) / kGrid, heightAt(x, y));
    text += "]\n  \"integer indices\" [\n";
    for (int y = 0; y + 1 < kGrid; ++y)
        for (int x = 0; x + 1 < kGrid; ++x) {
            const int i = y * kGrid + x;
            text += fmt::format("{} {} {} {} {} {}\n", i, i + 1, i + kGrid + 1, i, i + kGrid + 1, i + kGrid);
        }
    text += "]\n";
    std::ofstream(file, std::ios::binary) << text;
}

void writeBinaryPly(const fs::path& file) {
    const int triangles = 2 * (kGrid - 1) * (kGrid - 1);
    std::string out = fmt::format(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n"
        "property float y\nproperty float z\nelement face {}\n"
        "property list uchar int vertex_indices\nend_header\n",
        kGrid * kGrid, triangles);
    for (int y = 0; y < kGrid; ++y)
        for (int x = 0; x < kGrid; ++x) {
            const float p[3] = {float(x) / kGrid, float(y) / kGrid, heightAt(x, y)};
            out.append(reinterpret_cast<const char*>(p), sizeof(p));
        }
    for (int y = 0; y + 1 < kGrid; ++y)
        for (int x = 0; x + 1 < kGrid; ++x) {
            const int i = y * kGrid + x;
            const int faces[2][3] = {{i, i + 1, i + kGrid + 1}, {i, i + kGrid + 1, i + kGrid}};
            for (const auto& f : faces) {
                out += char(3);
                out.append(reinterpret_cast<const char*>(f), sizeof(f));
            }
        }
    std::ofstream(file, std::ios::binary) << out;
}

struct CountingTarget : pbrt::DirectiveTarget {
    size_t numbers = 0;
    void directive(pbrt::Directive&& d) override {
        for (const auto& p : d.parameters.parameters()) numbers += p.numbers.size();
    }
};

Scene quietLoad(const fs::path& file) {
    std::vector<std::string> warnings;
    return loadSceneFile(file, {{}, &warnings});
}

}  // namespace

int main(int argc, char** argv) {
    const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
    const fs::path dir = fs::temp_directory_path() / "penumbra_pbrt_parse_bench";
    fs::create_directories(dir);

    // 1. ASCII trianglemesh.
    const fs::path ascii = dir / "grid.pbrt";
    writeAsciiMesh(ascii);
    const double asciiMb = double(fs::file_size(ascii)) / 1e6;
    const double parseSeconds = bestSeconds(repeats, [&] {
        CountingTarget target;
        std::vector<fs::path> files;
        pbrt::parseSceneFile(ascii, target, files);
    });
    pbrt::PbrtConversion conversion;
    const double convertSeconds = bestSeconds(repeats, [&] { conversion = pbrt::convertPbrtFile(ascii); });
    const double buildSeconds = bestSeconds(repeats, [&] { pbrt::buildPbrtScene(conversion, ascii); });
    size_t triangles = 0;
    const double loadSeconds =
        bestSeconds(repeats, [&] { triangles = quietLoad(ascii).meshes.at(0).triangleCount(); });
    std::printf("ASCII trianglemesh, %zu triangles, %.1f MB:\n", triangles, asciiMb);
    std::printf("  parse (tokens, numbers, parameter lists): %.3f s, %.1f MB/s\n", parseSeconds,
                asciiMb / parseSeconds);
    std::printf("  parse and map to penumbra's format: %.3f s; build the scene from that: %.3f s\n",
                convertSeconds, buildSeconds);
    std::printf("  load (all of it): %.3f s, %.1f MB/s\n", loadSeconds, asciiMb / loadSeconds);

    // 2. Binary PLY named by a plymesh.
    writeBinaryPly(dir / "grid.ply");
    std::ofstream(dir / "ply.pbrt") << "WorldBegin\nShape \"plymesh\" \"string filename\" \"grid.ply\"\n";
    const double plyMb = double(fs::file_size(dir / "grid.ply")) / 1e6;
    const double plySeconds =
        bestSeconds(repeats, [&] { triangles = quietLoad(dir / "ply.pbrt").meshes.at(0).triangleCount(); });
    std::printf("binary PLY via plymesh, %zu triangles, %.1f MB: %.3f s, %.1f MB/s\n", triangles, plyMb,
                plySeconds, plyMb / plySeconds);

    // 3. The dragon from a .pbrt file against Embree's build of it.
    const char* env = std::getenv("PENUMBRA_DATA_DIR");
    const fs::path dragon =
        (env ? fs::path(env) : fs::path(PENUMBRA_DATA_DIR)) / "meshes" / "dragon_vrip.ply.gz";
    if (fs::exists(dragon)) {
        std::ofstream(dir / "dragon.pbrt")
            << "WorldBegin\nShape \"plymesh\" \"string filename\" \"" << dragon.string() << "\"\n";
        Scene scene;
        const double dragonLoad = bestSeconds(repeats, [&] { scene = quietLoad(dir / "dragon.pbrt"); });
        const double embreeBuild = bestSeconds(repeats, [&] { EmbreeAccelerator accel(scene); });
        std::printf(
            "dragon (%zu triangles, .ply.gz) from a .pbrt: load %.3f s, Embree build %.3f s, load / build = "
            "%.2f\n",
            scene.meshes.at(0).triangleCount(), dragonLoad, embreeBuild, dragonLoad / embreeBuild);
    } else {
        std::printf("dragon: %s not found, skipped\n", dragon.string().c_str());
    }
    fs::remove_all(dir);
    return 0;
}
