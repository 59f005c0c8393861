// The scene file's "media" section (participating media, one reader per type in one table), the
// media a shape bounds (its "inside" and "outside" keys) and the camera's medium. scenes/README.md
// documents the keys.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenes/json_reader.h"
#include "scenes/scene.h"

namespace penumbra {

// Adds the section's media to scene.media and their names to scene.mediumNames, in file order.
void readMedia(const JsonValue& section, const std::filesystem::path& folder, Scene& scene);

// A homogeneous medium's keys ("sigma_a" and "sigma_s", or a "preset", times "scale"; "g";
// "emission"): the "homogeneous" medium, and the interior of a "subsurface" material.
HomogeneousMedium readHomogeneousMedium(const JsonValue& value);

// A medium's name as an index into `names`; "" is the vacuum (MediumInterface::kVacuum).
uint32_t readMediumReference(const JsonValue& value, const std::vector<std::string>& names);

// A shape's "inside" and "outside" keys: the media on its two sides, the one not given being the
// vacuum; neither given, the shape is no boundary.
MediumInterface readMediumInterface(const JsonValue& shape, const std::vector<std::string>& names);

}  // namespace penumbra
