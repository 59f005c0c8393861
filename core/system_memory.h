// How much memory this machine can give now, so that a declared size (a resolution, a film
// file's windows) is refused with a message before it is allocated, not by std::bad_alloc or
// the OOM killer part way through.
#pragma once

#include <cstdint>
#include <string>

namespace penumbra {

struct SystemMemory {
    uint64_t availableBytes = 0;  // MemAvailable of /proc/meminfo; 0 when unknown
    uint64_t totalBytes = 0;      // MemTotal; 0 when unknown
};

// Reads /proc/meminfo (falls back to sysconf's physical pages for the total).
SystemMemory systemMemory();

// Throws InputError ("WHAT needs X GiB of memory; this machine has Y GiB available (of Z GiB)")
// when `bytes` exceed the available memory (or, when that is unknown, the total).
void requireMemory(double bytes, const std::string& what, const SystemMemory& memory = systemMemory());

}  // namespace penumbra
