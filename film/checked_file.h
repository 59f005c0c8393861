// A file written with every write, seek, fsync and close checked: a full disk or an I/O error is
// an exception at the call that met it, never a silently short file (as buffered streams give
// when their last flush, in a destructor, fails).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace penumbra {

class CheckedFile {
public:
    // Creates or truncates `path` for writing; throws std::runtime_error with the reason.
    explicit CheckedFile(const std::string& path);
    ~CheckedFile();  // closes without checking: call close() to know
    CheckedFile(const CheckedFile&) = delete;
    CheckedFile& operator=(const CheckedFile&) = delete;

    void write(const void* data, size_t size);
    uint64_t tell();
    void seek(uint64_t position);
    // fsync, then close: the data is on the disk, or the exception says why not. Also throws the
    // first failure of an earlier call, in case its caller swallowed it (OpenEXR writes its offset
    // tables in a destructor, which cannot let exceptions out).
    void close();

private:
    [[noreturn]] void fail(const char* operation);
    std::string path_;
    std::string firstError_;
    int fd_ = -1;
};

}  // namespace penumbra
