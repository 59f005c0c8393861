// Writing a file atomically: it is written under a temporary name in the destination folder and
// renamed over the destination once complete, so that a failed write leaves nothing behind.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace penumbra {

// Creates the destination's folder, then calls `write` with the temporary path (same folder, same
// extension, so that writers that pick the format from the extension still can), which writes the
// whole file there and returns true, or returns false with `error` set. On any failure the
// temporary file is removed and an InputError naming `path` is thrown:
// "cannot write the WHAT: reason". Temporaries of the same destination left by writers that were
// killed (SIGKILL, a crash) are removed first: those whose process is gone and that have not been
// modified for a minute.
void writeFileAtomically(const std::filesystem::path& path, const char* what,
                         const std::function<bool(const std::string& tmp, std::string& error)>& write);

}  // namespace penumbra
