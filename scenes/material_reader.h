// The scene file's "materials" section: name -> material, one reader per type in one table
// (material_reader.cpp). scenes/README.md documents the keys.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "materials/material.h"
#include "scenes/json_reader.h"
#include "scenes/material_interior.h"

namespace penumbra {

// Appends the section's materials and their names, in file order, and the media inside its
// subsurface materials to `interiors`. Image textures' relative paths are relative to `folder`
// (the scene file's).
void readMaterials(const JsonValue& section, const std::filesystem::path& folder,
                   std::vector<Material>& materials, std::vector<std::string>& names,
                   std::vector<MaterialInterior>& interiors);

// The index of the material a shape names; an unknown name fails with the names known.
uint32_t readMaterialReference(const JsonValue& value, const std::vector<std::string>& names);

}  // namespace penumbra
