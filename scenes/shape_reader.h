// The scene file's "prototypes" and "shapes" sections: meshes, quads, disks, spheres and instances,
// one reader per type in one table, with what shapes share (material, emission, transform,
// motion) (shape_reader.cpp). scenes/README.md documents the keys.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenes/json_reader.h"
#include "scenes/scene.h"

namespace penumbra {

// Appends the section's prototypes to scene.prototypes and their names to `names`, in file order.
// Mesh files' relative paths are relative to `folder` (the scene file's).
void readPrototypes(const JsonValue& section, const std::filesystem::path& folder, Scene& scene,
                    std::vector<std::string>& names);

// A "transform": an array of steps (translate, scale, rotate, matrix), applied in order, the first
// entry first. Media take one too.
Transform readTransform(const JsonValue& value);

// Appends the section's shapes to `scene`, in file order. They name the scene's materials (read
// before) and the prototypes that `prototypeNames` names; motion keys span its camera's shutter.
void readShapes(const JsonValue& section, const std::filesystem::path& folder,
                const std::vector<std::string>& prototypeNames, Scene& scene);

}  // namespace penumbra
