// Running a shell command (or the built `penumbra` program, PENUMBRA_BINARY) from a test and
// collecting its exit status and output.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace penumbra::testing {

struct RunResult {
    int exitCode = -1;   // -1 when the command could not be run or did not exit normally
    std::string output;  // stdout and stderr together
};

inline RunResult runShell(const std::string& command) {
    RunResult result;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

#ifdef PENUMBRA_BINARY
inline RunResult runPenumbra(const std::string& arguments) {
    return runShell(std::string(PENUMBRA_BINARY) + " " + arguments);
}
#endif

}  // namespace penumbra::testing
