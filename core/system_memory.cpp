#include "core/system_memory.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "core/error.h"

namespace penumbra {

SystemMemory systemMemory() {
    SystemMemory memory;
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line)) {
        unsigned long long kib = 0;
        if (std::sscanf(line.c_str(), "MemAvailable: %llu kB", &kib) == 1) memory.availableBytes = kib * 1024;
        if (std::sscanf(line.c_str(), "MemTotal: %llu kB", &kib) == 1) memory.totalBytes = kib * 1024;
    }
    if (memory.totalBytes == 0) {
        const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
        if (pages > 0 && pageSize > 0) memory.totalBytes = uint64_t(pages) * uint64_t(pageSize);
    }
    return memory;
}

void requireMemory(double bytes, const std::string& what, const SystemMemory& memory) {
    const double limit = double(memory.availableBytes ? memory.availableBytes : memory.totalBytes);
    if (limit <= 0 || bytes <= limit) return;
    char text[512];
    if (memory.availableBytes)
        std::snprintf(text, sizeof text,
                      "%s needs %.1f GiB of memory; this machine has %.1f GiB available (of %.1f GiB)",
                      what.c_str(), bytes / 0x1p30, double(memory.availableBytes) / 0x1p30,
                      double(memory.totalBytes) / 0x1p30);
    else
        std::snprintf(text, sizeof text, "%s needs %.1f GiB of memory; this machine has %.1f GiB",
                      what.c_str(), bytes / 0x1p30, double(memory.totalBytes) / 0x1p30);
    throw InputError(text);
}

}  // namespace penumbra
