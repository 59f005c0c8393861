// The checksum that a film's EXR carries over everything `render --resume` and `merge` trust: the
// metadata that says which samples the film holds, and every sum and sample count of the data
// window (docs/exr-layout.md, "Checksum"). OpenEXR's RLE has no check of its own, so a few flipped
// bytes would otherwise be read as a film with wrong pixels.
#pragma once

#include <cstdint>
#include <string>

#include "film/film.h"

namespace penumbra {

// The 64-bit checksum of the film's pixels in `window` (their 15 sums as 128-bit integers and their
// sample counts, row by row) and of `metadataText` (the attributes it depends on, as stored).
uint64_t filmChecksum(const Film& film, const PixelWindow& window, const std::string& metadataText);

// "h64:" and 16 hex digits, as the attribute penumbra:checksum stores it.
std::string formatFilmChecksum(uint64_t checksum);

}  // namespace penumbra
