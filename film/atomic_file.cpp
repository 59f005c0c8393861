#include "film/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>

#include <cerrno>
#include <cstring>

#include <system_error>

#include <fmt/format.h>

#include "core/error.h"

namespace penumbra {

namespace {

// "<folder>/<stem>.tmp-<pid><ext>": same folder (so the rename is atomic, never across file
// systems) and same extension.
std::filesystem::path temporaryPathFor(const std::filesystem::path& path) {
    std::filesystem::path tmp = path;
    tmp.replace_filename(fmt::format("{}.tmp-{}{}", path.stem().string(), long(::getpid()),
                                     path.extension().string()));
    return tmp;
}

// Whether process `pid` exists on this machine (a process of another user counts too).
bool processAlive(long pid) { return ::kill(pid_t(pid), 0) == 0 || errno == EPERM; }

// Removes what writers of `path` killed with SIGKILL left: "<stem>.tmp-<pid><ext>" files whose
// process is gone. A temporary modified in the last minute is kept even then: the folder may be
// shared with another machine, whose process numbers mean nothing here.
void removeStaleTemporaries(const std::filesystem::path& path) {
    const std::string prefix = path.stem().string() + ".tmp-", extension = path.extension().string();
    const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= prefix.size() + extension.size() || !name.starts_with(prefix) || !name.ends_with(extension))
            continue;
        const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - extension.size());
        if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const long pid = std::stol(digits);
        if (pid == long(::getpid()) || processAlive(pid)) continue;
        std::error_code ignored;
        const auto modified = std::filesystem::last_write_time(entry.path(), ignored);
        if (ignored || std::filesystem::file_time_type::clock::now() - modified < std::chrono::minutes(1)) continue;
        std::filesystem::remove(entry.path(), ignored);
    }
}

// fsync of a file or a folder; false with `error` set when it fails.
bool syncFile(const std::filesystem::path& path, std::string& error) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    bool ok = fd >= 0 && ::fsync(fd) == 0;
    if (!ok) error = fmt::format("cannot sync '{}' to the disk: {}", path.string(), std::strerror(errno));
    if (fd >= 0) ::close(fd);
    return ok;
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path, const char* what,
                         const std::function<bool(const std::string& tmp, std::string& error)>& write) {
    std::error_code ec;
    const std::filesystem::path parent = path.parent_path();
    if (!parent.empty()) {
        std::filesystem::create_directories(parent, ec);
        if (ec) throwFileError(path, fmt::format("cannot create folder '{}' for the {}: {}", parent.string(), what, ec.message()));
    }

    removeStaleTemporaries(path);
    const std::filesystem::path tmp = temporaryPathFor(path);
    auto cleanupAndFail = [&](const std::string& message) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throwFileError(path, fmt::format("cannot write the {}: {}", what, message));
    };

    std::string error;
    if (!write(tmp.string(), error)) cleanupAndFail(error);
    // On the disk before it takes the destination's name: a crash after the rename must not leave
    // a file whose blocks were never written (and a delayed write error shows here).
    if (!syncFile(tmp, error)) cleanupAndFail(error);
    std::filesystem::rename(tmp, path, ec);
    if (ec) cleanupAndFail(fmt::format("cannot rename '{}' to the destination: {}", tmp.string(), ec.message()));
    syncFile(parent.empty() ? std::filesystem::path(".") : parent, error);  // the rename; best effort
}

}  // namespace penumbra
