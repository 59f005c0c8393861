// A file written with every write, seek, fsync and close checked: a full disk or an I/O error is
// an exception at the call that met it, never a silently short file (as buffered streams give
// when their last flush, in a destructor, fails). Writes are gathered in a buffer of kBufferSize
// bytes and handed to the system when it is full, before a seek and at close() (OpenEXR writes a
// film in thousands of small pieces: a 128x128 film took 3,246 write calls, now 5), so
// a write's failure may surface at a later write, seek or close: never not at all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

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

    static constexpr size_t kBufferSize = size_t(1) << 20;

private:
    [[noreturn]] void fail(const char* operation);
    void writeThrough(const char* bytes, size_t size);  // to the file, checked
    void flush();
    std::string path_;
    std::vector<char> buffer_;  // written bytes not yet handed to the system
    std::string firstError_;
    int fd_ = -1;
};

}  // namespace penumbra
