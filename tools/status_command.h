// `penumbra status OUT.exr` (or OUT.parts.json): each part of a split render done, partial,
// started or missing, from the part files and logs alone (tools/part_status.h).
#pragma once

#include <string>

namespace penumbra {

// Prints one line a part and a summary; returns 0 (a status is not an error). Throws
// InputError when there is no readable manifest.
int runStatusCommand(const std::string& outputOrManifest);

}  // namespace penumbra
