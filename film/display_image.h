// The display-referred PNG/JPEG of a film, made through an OpenColorIO view transform and encoded
// by the image plugin (film/image_plugin.h, loaded on first use). Files are written under a
// temporary name in the destination folder and renamed, so no half-written image is ever left.
#pragma once

#include <filesystem>
#include <string>

#include "film/film.h"

namespace penumbra {

// How the display image is made: the OpenColorIO display and view (empty: the config's defaults)
// and an exposure in stops, applied to the scene-linear values before the view.
struct DisplayOptions {
    std::string display;
    std::string view;
    float exposure = 0.0f;
};

// 8-bit display image (format from the extension: .png, .jpg) through OpenColorIO: the config is
// $OCIO when set, otherwise penumbra's shipped config (film/ocio/config.ocio: views "Standard",
// "Filmic", "False Color", "Raw"); scene_linear to the options' display and view. The image
// records them in its "ImageDescription" and "penumbra:display", "penumbra:view" and
// "penumbra:exposure" attributes. Loads the image plugin, which encodes the file; throws
// InputError naming the plugin's file when it cannot be loaded.
void writeDisplayImage(const Film& film, const std::filesystem::path& path,
                       const DisplayOptions& options = {});
// Checks, before a render, that the config loads and has the options' display and view; throws
// InputError as writeDisplayImage would.
void checkDisplayOptions(const DisplayOptions& options);

}  // namespace penumbra
