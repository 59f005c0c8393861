// The film's scene-linear OpenEXR (docs/exr-layout.md), written and read with OpenEXR directly
// (film_exr.cpp): it holds the render's metadata, the beauty and AOVs (part "beauty") and the
// film's exact sums (parts "sums" and "sums.noise", so that a render can be resumed and partial
// renders merged bit for bit). Files are written under a temporary name in the destination folder
// and renamed, so no half-written film is ever left.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "core/adaptive_schedule.h"
#include "film/film.h"

namespace penumbra {

struct RenderMetadata {
    int samplesPerPixel = 0;  // samples each pixel of the window holds (endSample - firstSample)
    uint64_t seed = 0;
    std::string sampler;      // "stratified" / "independent"
    std::string accelerator;  // "embree" / "bvh"
    std::string sceneFile;
    std::string sceneHash;  // hashSceneFiles() of the scene file and its mesh files
    double renderSeconds = 0.0;
    std::string version;                      // penumbra version string
    uint32_t firstSample = 0, endSample = 0;  // every pixel of the window holds samples [first, end)
    std::optional<PixelWindow> crop;          // the pixels rendered; none: the whole image
    // An adaptive render's settings: each pixel of the window then holds samples [first, first + k)
    // for its own k <= end - first (its "spp" channel), k being a decision point of the settings'
    // schedule or end - first.
    std::optional<AdaptiveSettings> adaptive;
};

// Writes the film as a multi-part EXR (docs/exr-layout.md): part "beauty" holds FLOAT channels
// R, G, B, A, albedo.R/G/B, N.X/Y/Z, Z and variance.R/G/B with the metadata as header attributes
// "penumbra:spp", "penumbra:seed", "penumbra:sampler", "penumbra:accel", "penumbra:scene",
// "penumbra:sceneHash", "penumbra:renderTime", "penumbra:version", "penumbra:resolution",
// "penumbra:samples" ("FIRST:END") and "penumbra:crop" ("x0,x1,y0,y1"); parts "sums" and
// "sums.noise" hold the exact sums as UINT channels. With a crop the data window is the crop (the
// display window is the whole image). Throws InputError naming the path when it cannot be written.
//
// With FilmContents::Beauty only part "beauty" is written, marked with "penumbra:contents" =
// "beauty": about half the size, but it cannot be resumed or merged (readFilmExr refuses it).
enum class FilmContents { Full, Beauty };
void writeExr(const Film& film, const RenderMetadata& metadata, const std::filesystem::path& path,
              FilmContents contents = FilmContents::Full);

struct FilmFile {
    Film film;
    RenderMetadata metadata;
};

// Reads back a film written by writeExr, sums bit for bit. Throws InputError naming the path when
// it cannot be read or is not a film written by penumbra.
FilmFile readFilmExr(const std::filesystem::path& path);

// A film file's metadata and full resolution, read from its headers alone (no pixels): what a
// look at many large parts needs. Throws like readFilmExr when the headers are not a film's;
// pixels cut short by a killed writer are found only by readFilmExr.
struct FilmHeader {
    RenderMetadata metadata;
    int width = 0, height = 0;
};
FilmHeader readFilmHeader(const std::filesystem::path& path);

// Whether `path` is a full film written by writeExr (its first part has "penumbra:film" and no
// "penumbra:contents"); never throws.
bool isPenumbraFilm(const std::filesystem::path& path);

}  // namespace penumbra
