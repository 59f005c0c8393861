// Writing a file atomically: it is written under a temporary name in the destination folder and
// renamed over the destination once complete, so that a failed write leaves nothing behind.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace penumbra {

// Creates the destination's folder, then calls `write` with the temporary path, which writes the
// whole file there and returns true, or returns false with `error` set. The temporary path is
// "NAME.tmp-PID-XXXXXX/NAME" beside the destination: a new folder of this process's own (mkdtemp,
// mode 0700), so that no link planted in a shared folder can redirect the write, and the same file
// name, so that writers that pick the format from the extension still can. On any failure the
// temporary folder is removed and an InputError naming `path` is thrown:
// "cannot write the WHAT: reason". Temporaries of the same destination left by writers that were
// killed (SIGKILL, a crash) are removed first: this user's, whose process is gone and that have
// not been modified for a minute.
void writeFileAtomically(const std::filesystem::path& path, const char* what,
                         const std::function<bool(const std::string& tmp, std::string& error)>& write);

// `text` written atomically as above, with `addedPermissions` (e.g. the execute bits of a script)
// set on the temporary before it takes the destination's name.
void writeTextFileAtomically(const std::filesystem::path& path, const char* what, const std::string& text,
                             std::filesystem::perms addedPermissions = std::filesystem::perms::none);

}  // namespace penumbra
