// pbrt-v4's lens description files (its `realistic` camera's `lensfile`): text, `#` to the end of a
// line a comment, otherwise numbers four to a surface, front to back: curvature radius, thickness,
// index of refraction and aperture diameter, in millimetres (scenes/lenses/README.md).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "cameras/camera_params.h"

namespace penumbra {

// At most this many surfaces (the designs in use have 10 to 30).
inline constexpr size_t kMaxLensSurfaces = 256;

// The surfaces `text` describes; throws InputError at the file and line of the first problem: a
// word that is not a finite number, a row left incomplete, a negative thickness, index or
// diameter, a zero diameter, no surface, or more than kMaxLensSurfaces.
std::vector<LensSurface> parseLensFile(std::string_view text, const std::string& fileName);

// The file at `path`, read and parsed (at most 1 MiB).
std::vector<LensSurface> readLensFile(const std::filesystem::path& path);

}  // namespace penumbra
