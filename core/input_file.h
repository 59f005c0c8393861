// Opening what the user names as input (scene, mesh, film files, gzip-compressed or not) safely: a FIFO would
// block open() forever and /dev/zero would be read until memory runs out, so only regular files are read,
// opened without blocking, and only up to a documented size (core/input_limits.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace penumbra {

// An open, regular input file; closes itself.
class InputFile {
public:
    // Throws InputError naming `path` when it does not exist, is not a regular file (a folder, a
    // FIFO, a device), cannot be opened, or is larger than `maxBytes` ("the WHAT is N MiB; penumbra
    // reads at most M MiB").
    InputFile(const std::filesystem::path& path, const char* what, uint64_t maxBytes);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    int fd() const { return fd_; }
    uint64_t size() const { return size_; }
    // Hands the descriptor over (to zlib's gzdopen): it is no longer closed here.
    int release();
    // The whole file; throws InputError on a read error.
    std::string readAll();
    // The whole file decompressed from gzip (zlib reads an uncompressed file unchanged), at most
    // the `maxBytes` the file was opened with: a few megabytes of gzip can inflate to any size.
    // Throws InputError naming the file on corrupt or truncated data or beyond the limit.
    std::string readAllGzip();

private:
    std::filesystem::path path_;
    std::string what_;
    int fd_ = -1;
    uint64_t size_ = 0;
    uint64_t maxBytes_ = 0;
};

// "1.5 GiB", "300.0 MiB", "12 bytes": a size for messages.
std::string describeBytes(uint64_t bytes);

}  // namespace penumbra
