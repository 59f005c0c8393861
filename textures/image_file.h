// Reading a whole image file as linear RGB floats, for what needs every texel in memory (an
// environment map's sampling distribution). OpenEXR files are read with OpenEXR directly; other
// formats (Radiance .hdr, PNG, JPEG, TIFF, ...) through the texture plugin (textures/texture_plugin.h),
// which loads OpenImageIO on first use; 8-bit and 16-bit integer images are taken as sRGB-encoded
// and linearised there.
#pragma once

#include <filesystem>
#include <vector>

#include "core/error.h"
#include "core/rgb.h"

namespace penumbra {

struct LinearRgbImage {
    int width = 0, height = 0;
    std::vector<Rgb> texels;  // rows top to bottom
};

// Throws InputError at `where` (the scene key that names the file) when the file cannot be read,
// declares more than limits::kMaxImageTexels texels or 4 values a texel of that (checked from
// its header, before its pixels are allocated), or holds a texel that is not a radiance: NaN,
// infinite or negative (the message names the first one's position).
LinearRgbImage readLinearRgbImage(const std::filesystem::path& path, const SourceLocation& where);

}  // namespace penumbra
