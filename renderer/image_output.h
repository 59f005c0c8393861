// Writing the film: a scene-linear OpenEXR through OpenImageIO with the render's metadata, and a
// display-referred PNG/JPEG through an OpenColorIO view transform. Files are written under a
// temporary name in the destination folder and renamed, so no half-written image is ever left.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "renderer/film.h"

namespace penumbra {

struct RenderMetadata {
    int samplesPerPixel = 0;
    uint64_t seed = 0;
    std::string sampler;      // "stratified" / "independent"
    std::string accelerator;  // "embree" / "bvh"
    std::string sceneFile;
    double renderSeconds = 0.0;
    std::string version;      // penumbra version string
};

// Scene-linear RGB (half) with metadata as EXR header attributes named "penumbra:spp",
// "penumbra:seed", "penumbra:sampler", "penumbra:accel", "penumbra:scene", "penumbra:renderTime",
// "penumbra:version". Throws InputError naming the path when it cannot be written.
void writeExr(const Film& film, const RenderMetadata& metadata, const std::filesystem::path& path);

// 8-bit display image (format from the extension: .png, .jpg) through OpenColorIO: the config is
// $OCIO when set, otherwise penumbra's shipped config; scene_linear to the config's default
// display and view (sRGB) unless `display` / `view` name others.
void writeDisplayImage(const Film& film, const std::filesystem::path& path, const std::string& display = "",
                       const std::string& view = "");

}  // namespace penumbra
