// Reading a pbrt-v4 scene: the parser and the scene builder together, giving the scene in
// penumbra's own format (the JSON document `penumbra convert` writes) and the native loader's
// Scene built from it, with every error placed in the pbrt file (FILE:LINE:COLUMN).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "formats/pbrt/scene_builder.h"
#include "scenes/json_reader.h"
#include "scenes/scene.h"

namespace penumbra::pbrt {

struct PbrtConversion {
    Json document;                             // the scene in penumbra's format
    std::vector<Origin> origins;               // which directive each part comes from
    std::vector<std::filesystem::path> files;  // the scene file, every file it includes, spectrum files
    std::vector<std::string> warnings;         // one line each, with its count
};

// Reads a .pbrt file and what it includes. Throws InputError at FILE:LINE:COLUMN.
PbrtConversion convertPbrtFile(const std::filesystem::path& file);
// The same for text in memory; `file` names it and gives the folder relative names start from.
PbrtConversion convertPbrtText(std::string_view text, const std::filesystem::path& file);

// Builds the scene of a conversion (whose document may have been patched since) with the native
// loader. Errors the loader finds in the document are reported at the directive they come from.
Scene buildPbrtScene(const PbrtConversion& conversion, const std::filesystem::path& file);

}  // namespace penumbra::pbrt
