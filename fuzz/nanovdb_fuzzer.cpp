// NanoVDB files (readNanoVdbGridBytes), the grids "density" and "temperature" of each, then the grid
// read: as many values as cells, every value and the bounds finite, the bounds not empty, lookups
// finite. A grid breaking that aborts (a finding like a crash).
//
// The input is the file with its runs of zero bytes packed: a 0 byte followed by a LEB128 count
// stands for that many zeros (fuzz/nanovdb_pack.py packs and unpacks). A NanoVDB grid is at least
// 300 KB (its upper internal node alone is 270 KB, mostly zeros), far over the 64 KiB inputs
// scripts/fuzz.sh runs; packed, the seeds are a few kilobytes and a mutation changes the bytes of
// the grid it lands on, not the zeros between them.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "fuzz/fuzz_input.h"
#include "media/nanovdb_grid.h"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

// The unpacked file, at most 64 MiB (a packed input of 64 KiB can ask for far more; beyond this it
// is cut, which the reader sees as a truncated file).
std::vector<std::byte> unpack(const uint8_t* data, size_t size) {
    constexpr size_t kMaxBytes = size_t(64) << 20;
    std::vector<std::byte> out;
    for (size_t i = 0; i < size && out.size() < kMaxBytes;) {
        if (data[i] != 0) {
            out.push_back(std::byte{data[i++]});
            continue;
        }
        uint64_t count = 0;
        int shift = 0;
        for (++i; i < size && shift < 64; shift += 7) {
            const uint8_t b = data[i++];
            count |= uint64_t(b & 0x7f) << shift;
            if (!(b & 0x80)) break;
        }
        out.resize(out.size() + size_t(std::min<uint64_t>(count, kMaxBytes - out.size())));
    }
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    const std::vector<std::byte> bytes = unpack(data, size);
    for (const char* name : {"density", "temperature"})
        fuzz::expectReadOrInputError([&] {
            const DensityGrid grid = readNanoVdbGridBytes(bytes, "fuzz.nvdb", name);
            check(grid.nx > 0 && grid.ny > 0 && grid.nz > 0);
            check(grid.values.size() == size_t(grid.nx) * size_t(grid.ny) * size_t(grid.nz));
            for (const float v : grid.values) check(std::isfinite(v));
            const Vec3f lower = grid.bounds.lower, upper = grid.bounds.upper;
            check(std::isfinite(lower.x) && std::isfinite(lower.y) && std::isfinite(lower.z));
            check(std::isfinite(upper.x) && std::isfinite(upper.y) && std::isfinite(upper.z));
            check(lower.x < upper.x && lower.y < upper.y && lower.z < upper.z);
            for (const float t : {0.0f, 0.3f, 0.5f, 1.0f})
                check(std::isfinite(grid.lookup(lower + (upper - lower) * t)));
        });
    return 0;
}
