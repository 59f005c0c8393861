// The native scene format: JSON with comments, described in scenes/README.md.
#pragma once

#include <filesystem>
#include <string_view>

#include "scenes/json_reader.h"
#include "scenes/scene.h"

namespace penumbra {

// Reads and parses a scene file. Throws InputError naming the file when it cannot be read, and
// everything parseScene throws.
Scene loadScene(const std::filesystem::path& file);

// Parses scene text. `file` names the scene in messages, and mesh files are found relative to its
// folder. Every problem with the input throws InputError naming the file and either the line and
// column (JSON syntax) or the JSON pointer of the offending value (unknown keys, wrong types, values
// out of range, unknown material names), and what was expected. Mesh file errors name the mesh
// file and the shape that refers to it.
Scene parseScene(std::string_view jsonText, const std::filesystem::path& file);

// The same for a parsed document (a scene converted from another format, or patched).
Scene buildScene(const Json& document, const std::filesystem::path& file);

}  // namespace penumbra
