// pbrt-v4's participating media (MakeNamedMedium) as entries of penumbra's "media" section
// (scenes/README.md): "homogeneous", "uniformgrid" and "nanovdb", with pbrt-v4's defaults
// (sigma_a and sigma_s 1, scale 1, g 0). The mapping is stated in docs/pbrt-import.md.
#pragma once

#include <filesystem>

#include "formats/pbrt/materials.h"
#include "formats/pbrt/parameter_list.h"
#include "formats/pbrt/warning_log.h"
#include "scenes/json_reader.h"

namespace penumbra::pbrt {

// The medium MakeNamedMedium's `params` describe, placed by `transform` (penumbra's "transform"
// array: the medium's space to the world; null when it is the identity). Throws InputError at
// `where` or at a parameter for what pbrt-v4 refuses; warns for what penumbra leaves out.
// Files (nanovdb's "filename") are relative to `folder`, the scene file's.
Json mapMedium(const ParameterList& params, const Json& transform, const std::filesystem::path& folder,
               const TextureTable& textures, const SourceLocation& where, WarningLog& log);

}  // namespace penumbra::pbrt
