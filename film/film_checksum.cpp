#include "film/film_checksum.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <vector>

#include "core/hash.h"

namespace penumbra {

namespace {

// FNV-1a, 64 bits, of a string's bytes.
uint64_t fnv1a64(const std::string& text) {
    uint64_t h = 0xcbf29ce484222325ULL;
    for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ULL;
    return h;
}

// One row: each pixel's sums (the low then the high 64 bits of each 128-bit integer, in the
// order of PixelSums::sum) and its sample count, chained with hashCombine.
uint64_t rowChecksum(const Film& film, const PixelWindow& window, int y) {
    uint64_t h = mix64(uint64_t(y) + 0x9e3779b97f4a7c15ULL);
    for (int x = window.x0; x < window.x1; ++x) {
        const PixelSums& p = film.at(x, y);
        for (int s = 0; s < PixelSums::kSumCount; ++s) {
            uint32_t w[4];
            p.sum(s).toWords(w);
            h = hashCombine(h, uint64_t(w[0]) | uint64_t(w[1]) << 32);
            h = hashCombine(h, uint64_t(w[2]) | uint64_t(w[3]) << 32);
        }
        h = hashCombine(h, p.sampleCount);
    }
    return h;
}

}  // namespace

uint64_t filmChecksum(const Film& film, const PixelWindow& window, const std::string& metadataText) {
    // Rows are hashed in parallel, then chained in order: the result does not depend on threads.
    std::vector<uint64_t> rows(size_t(std::max(window.height(), 0)));
    tbb::parallel_for(0, int(rows.size()),
                      [&](int r) { rows[size_t(r)] = rowChecksum(film, window, window.y0 + r); });
    uint64_t h = mix64(fnv1a64(metadataText));
    for (uint64_t row : rows) h = hashCombine(h, row);
    return h;
}

std::string formatFilmChecksum(uint64_t checksum) { return fmt::format("h64:{:016x}", checksum); }

}  // namespace penumbra
