#include "film/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>

#include "core/error.h"

namespace penumbra {

namespace {

// The private folder a write goes through: "<folder>/<name>.tmp-<pid>-XXXXXX", made by mkdtemp,
// so with a name nobody could have chosen in advance and a mode (0700) that lets nobody else in.
// A file opened there by name cannot be a link planted by someone else, as a fixed temporary
// name in a shared folder could be; it is in the destination's folder, so the rename out of it is
// atomic (never across file systems).
std::filesystem::path makePrivateFolderFor(const std::filesystem::path& path, std::string& error) {
    std::filesystem::path pattern = path;
    pattern.replace_filename(fmt::format("{}.tmp-{}-XXXXXX", path.filename().string(), long(::getpid())));
    std::string name = pattern.string();
    if (!::mkdtemp(name.data())) {
        error = fmt::format("cannot make a temporary folder beside it: {}", std::strerror(errno));
        return {};
    }
    return name;
}

// Whether process `pid` exists on this machine (a process of another user counts too).
bool processAlive(long pid) { return ::kill(pid_t(pid), 0) == 0 || errno == EPERM; }

// Removes what writers of `path` killed with SIGKILL left: "<name>.tmp-<pid>-XXXXXX" folders of
// this user whose process is gone. One modified in the last minute is kept even then: the folder
// may be shared with another machine, whose process numbers mean nothing here.
void removeStaleTemporaries(const std::filesystem::path& path) {
    const std::string prefix = path.filename().string() + ".tmp-";
    const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (!name.starts_with(prefix)) continue;
        const std::string rest = name.substr(prefix.size());
        const size_t dash = rest.find('-');
        const std::string digits = rest.substr(0, dash);
        if (dash == std::string::npos || rest.size() - dash - 1 != 6 || digits.empty() || digits.size() > 9 ||
            digits.find_first_not_of("0123456789") != std::string::npos)
            continue;
        struct stat info;
        if (::lstat(entry.path().c_str(), &info) != 0 || !S_ISDIR(info.st_mode) || info.st_uid != ::geteuid())
            continue;
        const long pid = std::stol(digits);
        if (pid == long(::getpid()) || processAlive(pid)) continue;
        std::error_code ignored;
        const auto modified = std::filesystem::last_write_time(entry.path(), ignored);
        if (ignored || std::filesystem::file_time_type::clock::now() - modified < std::chrono::minutes(1))
            continue;
        std::filesystem::remove_all(entry.path(), ignored);
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
        if (ec)
            throwFileError(path, fmt::format("cannot create folder '{}' for the {}: {}", parent.string(),
                                             what, ec.message()));
    }

    removeStaleTemporaries(path);
    std::string error;
    const std::filesystem::path privateFolder = makePrivateFolderFor(path, error);
    if (privateFolder.empty()) throwFileError(path, fmt::format("cannot write the {}: {}", what, error));
    const std::filesystem::path tmp = privateFolder / path.filename();
    auto cleanupAndFail = [&](const std::string& message) {
        std::error_code ignored;
        std::filesystem::remove_all(privateFolder, ignored);
        throwFileError(path, fmt::format("cannot write the {}: {}", what, message));
    };

    if (!write(tmp.string(), error)) cleanupAndFail(error);
    // On the disk before it takes the destination's name: a crash after the rename must not leave
    // a file whose blocks were never written (and a delayed write error shows here).
    if (!syncFile(tmp, error)) cleanupAndFail(error);
    std::filesystem::rename(tmp, path, ec);
    if (ec)
        cleanupAndFail(fmt::format("cannot rename '{}' to the destination: {}", tmp.string(), ec.message()));
    std::filesystem::remove(privateFolder, ec);
    syncFile(parent.empty() ? std::filesystem::path(".") : parent, error);  // the rename; best effort
}

void writeTextFileAtomically(const std::filesystem::path& path, const char* what, const std::string& text,
                             std::filesystem::perms addedPermissions) {
    writeFileAtomically(path, what, [&](const std::string& tmp, std::string& error) {
        std::FILE* file = std::fopen(tmp.c_str(), "wb");
        if (!file) {
            error = fmt::format("cannot create '{}': {}", tmp, std::strerror(errno));
            return false;
        }
        const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
        const int writeErrno = errno;
        if (std::fclose(file) != 0 || !written) {
            error = fmt::format("write of '{}' failed: {}", tmp, std::strerror(written ? errno : writeErrno));
            return false;
        }
        std::error_code ec;
        if (addedPermissions != std::filesystem::perms::none)
            std::filesystem::permissions(tmp, addedPermissions, std::filesystem::perm_options::add, ec);
        if (ec) error = fmt::format("cannot set the permissions of '{}': {}", tmp, ec.message());
        return !ec;
    });
}

}  // namespace penumbra
