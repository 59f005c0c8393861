#include "film/checked_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace penumbra {

CheckedFile::CheckedFile(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) fail("open");
    buffer_.reserve(kBufferSize);
}

CheckedFile::~CheckedFile() {
    if (fd_ >= 0) ::close(fd_);
}

void CheckedFile::fail(const char* operation) {
    const std::string error = fmt::format("{} of '{}' failed: {}", operation, path_, std::strerror(errno));
    if (firstError_.empty()) firstError_ = error;
    throw std::runtime_error(error);
}

void CheckedFile::write(const void* data, size_t size) {
    const char* bytes = static_cast<const char*>(data);
    if (buffer_.size() + size > kBufferSize) flush();
    if (size >= kBufferSize) {
        writeThrough(bytes, size);
        return;
    }
    buffer_.insert(buffer_.end(), bytes, bytes + size);
}

void CheckedFile::flush() {
    // After a failure the bytes stay in the buffer; close() throws the first failure regardless.
    writeThrough(buffer_.data(), buffer_.size());
    buffer_.clear();
}

void CheckedFile::writeThrough(const char* bytes, size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd_, bytes, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n == 0) errno = ENOSPC;  // no progress: a full device
            fail("write");
        }
        bytes += n;
        size -= size_t(n);
    }
}

uint64_t CheckedFile::tell() {
    const off_t position = ::lseek(fd_, 0, SEEK_CUR);
    if (position < 0) fail("seek");
    return uint64_t(position) + buffer_.size();
}

void CheckedFile::seek(uint64_t position) {
    flush();
    if (::lseek(fd_, off_t(position), SEEK_SET) < 0) fail("seek");
}

void CheckedFile::close() {
    if (!firstError_.empty()) throw std::runtime_error(firstError_);
    flush();
    if (::fsync(fd_) != 0) fail("fsync");
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail("close");
}

}  // namespace penumbra
