#include "scenes/material_interior.h"

#include <fmt/format.h>

namespace penumbra {

std::vector<uint32_t> addMaterialInteriors(const std::vector<MaterialInterior>& interiors, Scene& scene) {
    std::vector<uint32_t> interiorOf(scene.materials.size(), MediumInterface::kVacuum);
    if (!interiors.empty()) scene.firstMaterialInterior = uint32_t(scene.media.size());
    for (const MaterialInterior& interior : interiors) {
        interiorOf[interior.material] = uint32_t(scene.media.size());
        scene.media.push_back(interior.medium);
        scene.mediumNames.push_back(
            fmt::format("(inside of material \"{}\")", scene.materialNames[interior.material]));
    }
    return interiorOf;
}

namespace {

template <class Shape>
void fillInteriors(const std::vector<uint32_t>& interiorOf, std::vector<Shape>& shapes) {
    for (Shape& shape : shapes)
        if (shape.media.inside == MediumInterface::kVacuum && shape.material < interiorOf.size())
            shape.media.inside = interiorOf[shape.material];
}

}  // namespace

void fillShapeInteriors(const std::vector<uint32_t>& interiorOf, Scene& scene) {
    fillInteriors(interiorOf, scene.meshes);
    fillInteriors(interiorOf, scene.spheres);
    fillInteriors(interiorOf, scene.curves);
    fillInteriors(interiorOf, scene.patches);
    fillInteriors(interiorOf, scene.instances);
}

}  // namespace penumbra
