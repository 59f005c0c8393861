// Running another program (sbatch, squeue, scancel, python3) with its arguments as they are: no
// shell reads them, so no value in them can become a command.
#pragma once

#include <string>
#include <vector>

namespace penumbra {

struct ProgramResult {
    int exitStatus = -1;  // -1 when it could not be started or did not exit normally
    std::string output;   // stdout and stderr together
};

// Runs `arguments[0]` (looked up on PATH when it has no '/') with `arguments`, waits for it and
// collects its output. `arguments` must not be empty.
ProgramResult runProgram(const std::vector<std::string>& arguments);

// The arguments as one line a user could paste into a shell (each shell-quoted), for messages.
std::string commandLineFor(const std::vector<std::string>& arguments);

}  // namespace penumbra
