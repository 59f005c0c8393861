// The one place that picks a scene reader by the file's extension: penumbra's JSON format
// (scene_loader.h) or pbrt-v4's (pbrt/pbrt_reader.h). Every tool loads scenes through it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenes/scene.h"

namespace penumbra {

struct SceneFileOptions {
    // A JSON merge patch (RFC 7386) applied to the scene in penumbra's format before it is built:
    // changes a converted pbrt scene (or a JSON one) without editing it, e.g.
    // {"integrator": {"max_depth": 1}, "materials": {"Rough": {"distribution": "beckmann"}}}.
    std::filesystem::path patch;
    // Where warnings go (one line each, "FILE:LINE:COLUMN: message (N times)"); null: printed to
    // stderr as "penumbra: warning: ...".
    std::vector<std::string>* warnings = nullptr;
};

// Whether `file` is read as a pbrt-v4 scene (its extension is .pbrt).
bool isPbrtScene(const std::filesystem::path& file);

// Loads a scene file of either format. Throws InputError with the place of any problem.
Scene loadSceneFile(const std::filesystem::path& file, const SceneFileOptions& options = {});

// `penumbra convert`: the pbrt-v4 scene `file` as penumbra's JSON, to be written to `output`:
// mesh files stay where they are and are named relative to `output`'s folder. Warnings go as for
// loadSceneFile.
std::string convertSceneToJson(const std::filesystem::path& file, const std::filesystem::path& output,
                               std::vector<std::string>* warnings = nullptr);

}  // namespace penumbra
