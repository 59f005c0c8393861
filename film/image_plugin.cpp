// penumbra_image_plugin: the OpenImageIO side of film/image_plugin.h. Built as a module and
// loaded on first use, so that the penumbra executable does not link OpenImageIO.
#include "film/image_plugin.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

namespace {

int failWith(const std::string& message, char* error, size_t errorSize) {
    if (errorSize > 0) {
        const size_t n = std::min(message.size(), errorSize - 1);
        std::memcpy(error, message.data(), n);
        error[n] = '\0';
    }
    return 0;
}

// Writes `bytes` to `path` with every write, the fsync and the close checked; "" or the reason.
std::string writeWholeFile(const char* path, const std::vector<unsigned char>& bytes) {
    const int fd = ::open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return std::string("open failed: ") + std::strerror(errno);
    std::string failure;
    for (size_t done = 0; done < bytes.size() && failure.empty();) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            failure = std::string("write failed: ") + std::strerror(n == 0 ? ENOSPC : errno);
        else
            done += size_t(n);
    }
    if (failure.empty() && ::fsync(fd) != 0) failure = std::string("fsync failed: ") + std::strerror(errno);
    if (::close(fd) != 0 && failure.empty()) failure = std::string("close failed: ") + std::strerror(errno);
    return failure;
}

int writeRgb8(const char* path, int width, int height, const unsigned char* rgb,
              const char* const* attributes, int quality, char* error, size_t errorSize) {
    try {
        // Encoded in memory, then written with every call checked: OpenImageIO's PNG writer ignores
        // the failure of its final fclose, so a full disk left an empty PNG and no error.
        auto out = OIIO::ImageOutput::create(path);
        if (!out) return failWith(OIIO::geterror(), error, errorSize);
        std::vector<unsigned char> encoded;
        OIIO::Filesystem::IOVecOutput memory(encoded);
        if (!out->set_ioproxy(&memory))
            return failWith("the image writer cannot encode into memory", error, errorSize);
        OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
        for (const char* const* a = attributes; a && a[0] && a[1]; a += 2) spec.attribute(a[0], a[1]);
        if (quality > 0) spec.attribute("Compression", "jpeg:" + std::to_string(quality));
        if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb) || !out->close())
            return failWith(out->geterror(), error, errorSize);
        const std::string failure = writeWholeFile(path, encoded);
        if (!failure.empty()) return failWith(failure, error, errorSize);
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

int readInfo(const char* path, PenumbraImageInfo* info, char* error, size_t errorSize) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        const OIIO::ImageSpec& spec = in->spec();
        *info =
            PenumbraImageInfo{spec.full_width, spec.full_height, spec.x, spec.y, spec.width, spec.height, {}};
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) info->rgbChannel[c] = spec.channelindex(names[c]);
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

int readRgb(const char* path, float* rgb, char* error, size_t errorSize) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        const OIIO::ImageSpec& spec = in->spec();
        int channel[3];
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            if ((channel[c] = spec.channelindex(names[c])) < 0)
                return failWith(std::string("no channel '") + names[c] + "'", error, errorSize);
        std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
            return failWith(in->geterror(), error, errorSize);
        for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
            for (int c = 0; c < 3; ++c) rgb[3 * p + c] = pixels[p * spec.nchannels + channel[c]];
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const PenumbraImagePlugin* penumbra_image_plugin() {
    static const PenumbraImagePlugin plugin{kPenumbraImagePluginVersion, writeRgb8, readInfo, readRgb};
    return &plugin;
}
