#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace penumbra {

namespace {

const char* kindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

}  // namespace

std::string describeBytes(uint64_t bytes) {
    char text[64];
    if (bytes >= (uint64_t(1) << 30))
        std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / 0x1p30);
    else if (bytes >= (uint64_t(1) << 20))
        std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / 0x1p20);
    else
        std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
    return text;
}

InputFile::InputFile(const std::filesystem::path& path, const char* what, uint64_t maxBytes)
    : path_(path), what_(what), maxBytes_(maxBytes) {
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer, forever.
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
        if (errno == ENOENT) throwFileError(path, std::string(what) + " not found");
        throwFileError(path,
                       std::string("cannot open the ") + what + " for reading: " + std::strerror(errno));
    }
    struct stat status {};
    if (::fstat(fd_, &status) != 0) {
        const int error = errno;
        ::close(fd_);
        throwFileError(path, std::string("cannot read the ") + what + ": " + std::strerror(error));
    }
    if (!S_ISREG(status.st_mode)) {
        ::close(fd_);
        throwFileError(path, std::string("is ") + kindOf(status.st_mode) +
                                 ", not a regular file; penumbra reads the " + what +
                                 " only from a regular file");
    }
    size_ = uint64_t(status.st_size);
    if (size_ > maxBytes) {
        ::close(fd_);
        throwFileError(path, "the " + std::string(what) + " is " + describeBytes(size_) +
                                 "; penumbra reads at most " + describeBytes(maxBytes) + " (docs/limits.md)");
    }
}

InputFile::~InputFile() {
    if (fd_ >= 0) ::close(fd_);
}

int InputFile::release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
}

std::string InputFile::readAll() {
    std::string bytes(size_, '\0');
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::read(fd_, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throwFileError(path_, std::string("cannot read the file: ") + std::strerror(errno));
        if (n == 0) break;  // the file shrank while being read
        done += size_t(n);
    }
    bytes.resize(done);
    return bytes;
}

std::string InputFile::readAllGzip() {
    gzFile gz = gzdopen(fd_, "rb");
    if (!gz) throwFileError(path_, "cannot open the " + what_ + " for reading");
    release();  // gzclose closes it now
    std::string out;
    std::vector<char> buffer(1 << 20);
    int n = 0;
    while ((n = gzread(gz, buffer.data(), unsigned(buffer.size()))) > 0) {
        if (out.size() + size_t(n) > maxBytes_) {
            gzclose(gz);
            throwFileError(path_, "the " + what_ + " decompresses to more than " + describeBytes(maxBytes_) +
                                      ", penumbra's limit (docs/limits.md)");
        }
        out.append(buffer.data(), size_t(n));
    }
    // A truncated stream reads as a short file; zlib reports it through gzerror and gzclose.
    int code = Z_OK;
    const std::string reason = gzerror(gz, &code);
    const int closed = gzclose(gz);
    if (n < 0 || code != Z_OK || closed != Z_OK)
        throwFileError(path_, "cannot decompress the gzip data: " +
                                  (n < 0 || code != Z_OK ? reason : "the compressed stream is truncated"));
    return out;
}

}  // namespace penumbra
