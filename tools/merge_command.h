// `penumbra merge PART... -o OUT.exr`: the parts added into one film (film/film_merge.h).
#pragma once

#include <string>
#include <vector>

namespace penumbra {

// Writes OUT.exr (and OUT.png unless noDisplay); returns the exit status. Nothing is written
// when a check fails.
int runMergeCommand(const std::vector<std::string>& parts, const std::string& output, bool noDisplay, bool quiet);

}  // namespace penumbra
