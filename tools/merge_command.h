// `penumbra merge PART... -o OUT.exr`: the parts added into one film (film/film_merge.h), and
// `penumbra merge --manifest OUT.parts.json [--group G]`: the parts of a split render
// (tools/part_manifest.h), each checked done first.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// Writes OUT.exr (and OUT.png unless noDisplay); returns the exit status. Nothing is written
// when a check fails.
int runMergeCommand(const std::vector<std::string>& parts, const std::string& output, bool noDisplay,
                    bool quiet);

// Merges the parts the manifest lists into its output (or `output` when not empty), or with
// `group` only that merge group's parts into the group's file. Throws InputError, writing
// nothing, when a part is missing or incomplete (naming each with its range) or the merged film
// is not exactly the render the manifest describes.
int runManifestMerge(const std::string& manifestPath, std::optional<int> group, const std::string& output,
                     bool noDisplay, bool quiet);

}  // namespace penumbra
