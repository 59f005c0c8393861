// The limits on what penumbra reads, in one place (docs/limits.md lists them with the reasons).
// Each is generous for any real scene; beyond it an input is refused with a message, rather than
// hanging, overflowing or exhausting memory.
#pragma once

#include <cstdint>

namespace penumbra::limits {

// Image width and height (scene "film.resolution", --res, a film's EXR windows).
constexpr int kMaxImageSide = 1 << 16;

// Worker threads (--threads). TBB's arena teardown crashes beyond 65536; no machine has 4096 cores.
constexpr int kMaxThreads = 4096;

}  // namespace penumbra::limits
