#include "scenes/scene_loader.h"

#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/input_file.h"
#include "core/input_limits.h"
#include "scenes/camera_reader.h"
#include "scenes/environment_reader.h"
#include "scenes/json_reader.h"
#include "scenes/light_reader.h"
#include "scenes/material_reader.h"
#include "scenes/medium_reader.h"
#include "scenes/settings_reader.h"
#include "scenes/shape_reader.h"

namespace penumbra {

namespace fs = std::filesystem;

Scene parseScene(std::string_view jsonText, const fs::path& file) {
    return buildScene(parseJsonText(jsonText, file.string()), file);
}

Scene buildScene(const Json& document, const fs::path& file) {
    const std::string fileName = file.string();
    const JsonValue root(document, fileName, "");
    if (!document.is_object()) root.failExpected("a JSON object holding the scene's sections");
    const JsonObject top(root, {"camera", "film", "integrator", "render", "background", "environment",
                                "materials", "media", "prototypes", "shapes", "lights"});

    Scene scene;
    scene.sourcePath = file;
    const fs::path folder = file.parent_path();
    if (auto v = top.get("camera")) scene.camera = readCamera(*v, folder);
    if (auto v = top.get("film")) scene.film = readFilm(*v);
    // An equal-area spherical image is square (its octahedral map covers the square).
    if (scene.camera.projection == CameraProjection::Spherical &&
        scene.camera.sphericalMapping == SphericalMapping::EqualArea && scene.film.width != scene.film.height)
        top.get("camera")->requiredMember("mapping").fail(
            fmt::format("an equal-area spherical image is square; the film is {}x{}", scene.film.width,
                        scene.film.height));
    if (auto v = top.get("integrator")) scene.integrator = readIntegrator(*v);
    if (auto v = top.get("render")) scene.settings = readRender(*v);
    if (auto v = top.get("background")) scene.environment = readBackground(*v);
    if (auto v = top.get("environment")) {
        if (top.get("background")) v->fail("give either \"background\" or \"environment\", not both");
        scene.environment = readEnvironment(*v, file.parent_path());
    }
    // Materials before the shapes that name them.
    std::vector<MaterialInterior> interiors;
    if (auto v = top.get("materials"))
        readMaterials(*v, folder, scene.materials, scene.materialNames, interiors);
    if (auto v = top.get("media")) readMedia(*v, folder, scene);  // before the shapes and camera naming them
    const std::vector<uint32_t> interiorOf = addMaterialInteriors(interiors, scene);
    if (auto camera = top.get("camera"))
        if (auto v = camera->member("medium"))
            scene.cameraMedium = readMediumReference(*v, scene.mediumNames);
    std::vector<std::string> prototypeNames;  // prototypeNames[i] names scene.prototypes[i]
    if (auto v = top.get("prototypes"))
        readPrototypes(*v, folder, scene, prototypeNames);  // before the instances that name them
    if (auto v = top.get("shapes")) readShapes(*v, folder, prototypeNames, scene);
    fillShapeInteriors(interiorOf, scene);
    if (auto v = top.get("lights")) readLights(*v, folder, scene);
    return scene;
}

Scene loadScene(const fs::path& file) {
    // A regular file of bounded size: not a FIFO, a device or a file that parses into gigabytes.
    return parseScene(InputFile(file, "scene file", limits::kMaxSceneFileBytes).readAll(), file);
}

}  // namespace penumbra
