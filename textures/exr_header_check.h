// Checking an OpenEXR file's headers before OpenEXR's C++ reader opens it (ours reads environment
// maps, OpenImageIO's reads textures). That reader allocates what a header declares before it
// reads it (an attribute's size, a table of every chunk's offset) and reads some attributes past
// their declared size; OpenEXR's C core parses headers checking every declared size against the
// file's (film/film_exr.cpp found the same for films).
#pragma once

#include <cstdint>
#include <string>

namespace penumbra {

// Whether the file starts with OpenEXR's magic number (OpenImageIO chooses a reader by the
// contents when the extension does not fit, so the name does not decide).
bool startsLikeExr(const char* path);

// Parses every header with OpenEXR's C core in strict mode and checks each part against the
// limits (core/input_limits.h): at most `maxTexels` texels in its data window and in a tile, at
// most kMaxImageChannels channels and kMaxValuesPerTexel x `maxTexels` values, no deep
// data, at most kMaxExrChunks chunks in all. Returns
// what is wrong, or an empty string. Compiled into the texture plugin too, so it throws nothing.
std::string exrHeaderProblem(const char* path, int64_t maxTexels);

}  // namespace penumbra
