// The interface of the image plugin, penumbra_image_plugin: a module, loaded with dlopen on first
// use, that holds everything that needs OpenImageIO (encoding PNG/JPEG, reading arbitrary
// images). OpenImageIO pulls in some 260 shared libraries, whose loading would otherwise slow
// every penumbra process's start-up (bench/README.md, "Speed tricks").
//
// A plain C interface, so that no C++ object or exception crosses the module boundary: every
// function returns 1 on success, or 0 with a NUL-terminated reason written to `error` (at most
// `errorSize` bytes), which the caller turns into an InputError naming the file.
#pragma once

#include <stddef.h>

extern "C" {

// The image's display window (fullWidth x fullHeight), its data window (x, y, width, height) and
// the indices of its R, G and B channels (-1 where missing).
struct PenumbraImageInfo {
    int fullWidth, fullHeight;
    int x, y, width, height;
    int rgbChannel[3];
};

struct PenumbraImagePlugin {
    int version;  // kPenumbraImagePluginVersion
    // Writes 8-bit RGB pixels (width x height x 3, rows top to bottom) to `path`, in the format its
    // extension names, with the string attributes `attributes` (name, value, name, value, ...,
    // then NULL; e.g. "Software"); `quality` is the JPEG quality (0 for PNG).
    int (*writeRgb8)(const char* path, int width, int height, const unsigned char* rgb,
                     const char* const* attributes, int quality, char* error, size_t errorSize);
    // Describes the image at `path`.
    int (*readInfo)(const char* path, PenumbraImageInfo* info, char* error, size_t errorSize);
    // Reads the R, G and B channels of the data window as floats (width x height x 3).
    int (*readRgb)(const char* path, float* rgb, char* error, size_t errorSize);
};

#define PENUMBRA_IMAGE_PLUGIN_ENTRY "penumbra_image_plugin"
typedef const PenumbraImagePlugin* (*PenumbraImagePluginEntry)(void);

}  // extern "C"

constexpr int kPenumbraImagePluginVersion = 2;
