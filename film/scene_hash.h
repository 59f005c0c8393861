// What identifies the scene a film was rendered from: a hash of the bytes of its files, recorded
// in the film's metadata (film/film_exr.h) and compared before a resume or a merge.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra {

// "fnv1a64:<16 hex digits>" of a file's bytes. Throws InputError naming the path when it cannot
// be read.
std::string hashFileContents(const std::filesystem::path& path);
// The same over the scene file's bytes followed by those of each mesh file it names
// (Scene::meshFiles): identifies the scene a film was rendered from, so that a resume or a merge
// refuses a film rendered before a mesh file changed. A scene without mesh files hashes as its
// file alone (as films written before mesh files were hashed record it).
std::string hashSceneFiles(const std::filesystem::path& sceneFile,
                           const std::vector<std::filesystem::path>& meshFiles);

}  // namespace penumbra
