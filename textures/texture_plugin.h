// The interface of the texture plugin, penumbra_texture_plugin: a module, loaded with dlopen the
// first time a scene names an image (film/image_plugin.h explains why OpenImageIO is kept out of
// the executable: some 260 shared libraries, loaded at every start-up). It holds one
// OpenImageIO TextureSystem (tiled, MIP-mapped, cached, thread-safe) for the whole process.
//
// A plain C interface, so that no C++ object or exception crosses the module boundary: functions
// that can fail return 1 on success, or 0 with a NUL-terminated reason written to `error` (at most
// `errorSize` bytes), which the caller turns into an InputError naming the scene key.
#pragma once

#include <stddef.h>

extern "C" {

// How an image texture is looked up (OpenImageIO's TextureOpt).
enum PenumbraTextureWrap {
    PENUMBRA_WRAP_REPEAT = 0,
    PENUMBRA_WRAP_CLAMP = 1,
    PENUMBRA_WRAP_BLACK = 2,
    PENUMBRA_WRAP_MIRROR = 3
};
enum PenumbraTextureFilter {
    PENUMBRA_FILTER_CLOSEST = 0,     // the nearest texel of the finest level
    PENUMBRA_FILTER_BILINEAR = 1,    // bilinear in the finest level, no MIP-mapping
    PENUMBRA_FILTER_TRILINEAR = 2,   // bilinear in the two MIP levels around the footprint, blended
    PENUMBRA_FILTER_ANISOTROPIC = 3  // several trilinear probes along the footprint's long axis (EWA-like)
};
enum PenumbraColorSpace { PENUMBRA_COLOR_AUTO = 0, PENUMBRA_COLOR_SRGB = 1, PENUMBRA_COLOR_LINEAR = 2 };

struct PenumbraTextureInfo {
    int width, height, channels;
    int convertedFromSrgb;  // 1 when the texels were sRGB-encoded and are looked up linearised
};

struct PenumbraTexturePlugin {
    int version;  // kPenumbraTexturePluginVersion
    // Opens the image at `path` for lookups: returns a handle in `*handle` (valid for the process's
    // life). Only OpenEXR, PNG, JPEG, TIFF and Radiance HDR files are read (by their first bytes).
    // First the header is checked against the limits of an image texture
    // (core/input_limits.h: kMaxTextureTexels at every MIP level, the channels and values; an OpenEXR
    // file's headers by OpenEXR's C core, textures/exr_header_check.h), before anything is read
    // or allocated for its pixels.
    // Integer-valued images are sRGB-encoded unless `colorSpace` says linear (AUTO: integer
    // formats are sRGB, float formats linear); those are linearised texel by texel with
    // OpenImageIO's built-in sRGB -> linear conversion (ImageBufAlgo::colorconvert) into a tiled
    // half-float OpenEXR file in a temporary folder of the process, removed when the process exits.
    // Other images are looked up in place. Those without MIP levels (the linearised ones included)
    // get them built in memory by the TextureSystem ("automip").
    int (*openTexture)(const char* path, int colorSpace, void** handle, PenumbraTextureInfo* info,
                       char* error, size_t errorSize);
    // Filtered lookup of the first `channels` channels at (s, t) (t = 0 is the image's top) with
    // the footprint's derivatives; `result` receives `channels` floats. A lookup that fails (a
    // truncated or corrupt file, found only when its tiles are read) gives black and is recorded:
    // takeLookupFailures() reports it.
    void (*lookup)(void* handle, int wrapS, int wrapT, int filter, float s, float t, float dsdx, float dtdx,
                   float dsdy, float dtdy, int channels, float* result);
    // The image's size from its header, checked as openTexture() checks a texture's but against
    // `maxTexels` (an environment map's limit).
    int (*probeImage)(const char* path, long long maxTexels, int* width, int* height, char* error,
                      size_t errorSize);
    // The image's first three channels as linear floats (3 a texel, rows top to bottom; a
    // one-channel image is grey), linearised as openTexture() does with AUTO, handed to `strip` a
    // strip of `rows` whole rows at a time, in order, so that the caller's memory grows only with
    // what decodes. Fails when the file is not of the size given (that probeImage() found).
    int (*readLinearRgb)(const char* path, int width, int height,
                         void (*strip)(void* user, const float* rgb, int rows), void* user, char* error,
                         size_t errorSize);
    // The TextureSystem's statistics as text (OpenImageIO's getstats at `level` 1..5), NUL-terminated.
    void (*statistics)(int level, char* text, size_t textSize);
    // The counters the render summary prints: lookups, files opened, bytes read from files, and
    // the peak memory of the tile cache.
    void (*counters)(unsigned long long* lookups, unsigned long long* files, unsigned long long* bytesRead,
                     unsigned long long* peakCacheBytes);
    // The lookups that failed since the last call, and the first one's file and OpenImageIO's
    // message ("PATH: message", NUL-terminated, in `first`); then counts from zero again.
    unsigned long long (*takeLookupFailures)(char* first, size_t firstSize);
    // Drops what the TextureSystem holds of the file at `path` (its tiles, its linearised
    // conversion), so that a file rewritten under the same name is read again.
    void (*forget)(const char* path);
};

#define PENUMBRA_TEXTURE_PLUGIN_ENTRY "penumbra_texture_plugin"
typedef const PenumbraTexturePlugin* (*PenumbraTexturePluginEntry)(void);

}  // extern "C"

constexpr int kPenumbraTexturePluginVersion = 3;
