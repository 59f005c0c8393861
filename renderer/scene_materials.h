// The scene's material descriptions turned into the closed set the integrator evaluates.
#pragma once

#include <vector>

#include "materials/material.h"
#include "scenes/scene.h"

namespace penumbra {

// One Material per Scene::materials entry, in the same order (shapes refer to them by index).
std::vector<Material> buildMaterials(const Scene& scene);

}  // namespace penumbra
