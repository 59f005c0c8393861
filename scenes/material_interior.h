// The media that materials bring: a "subsurface" material (scenes/material_reader.cpp) is a
// dielectric boundary around a homogeneous medium that fills every shape using the material. The
// loader adds those media to the scene after the file's own "media" (each named after its
// material) and makes each such shape's inside that medium, unless the shape names an "inside"
// medium itself; the outside stays what the shape names (the vacuum by default).
#pragma once

#include <cstdint>
#include <vector>

#include "media/homogeneous_medium.h"
#include "scenes/scene.h"

namespace penumbra {

struct MaterialInterior {
    uint32_t material;  // index into Scene::materials
    HomogeneousMedium medium;
};

// Appends the interiors' media to scene.media (with their names); returns, per material of the
// scene, the index of its interior medium, or MediumInterface::kVacuum.
std::vector<uint32_t> addMaterialInteriors(const std::vector<MaterialInterior>& interiors, Scene& scene);

// Gives every shape whose material has an interior medium and whose inside is the vacuum that
// medium (`interiorOf` as addMaterialInteriors returns it).
void fillShapeInteriors(const std::vector<uint32_t>& interiorOf, Scene& scene);

}  // namespace penumbra
