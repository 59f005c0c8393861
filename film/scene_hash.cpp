#include "film/scene_hash.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

#include "core/error.h"
#include "core/input_file.h"

namespace penumbra {

namespace {

constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;  // FNV-1a, 64 bits

// Continues the FNV-1a hash `hash` over the bytes of the file at `path`.
void hashBytesOf(const std::filesystem::path& path, uint64_t& hash) {
    InputFile in(path, "file to hash", UINT64_MAX);  // a regular file only: a FIFO would block
    char buffer[1 << 16];
    while (true) {
        const ssize_t n = ::read(in.fd(), buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throwFileError(path, "cannot read the file to hash it");
        if (n == 0) break;
        for (ssize_t i = 0; i < n; ++i) {
            hash ^= uint8_t(buffer[i]);
            hash *= 0x100000001b3ull;
        }
    }
}

std::string formatHash(uint64_t hash) { return fmt::format("fnv1a64:{:016x}", hash); }

}  // namespace

std::string hashFileContents(const std::filesystem::path& path) {
    uint64_t hash = kFnvOffsetBasis;
    hashBytesOf(path, hash);
    return formatHash(hash);
}

std::string hashSceneFiles(const std::filesystem::path& sceneFile,
                           const std::vector<std::filesystem::path>& meshFiles) {
    uint64_t hash = kFnvOffsetBasis;
    hashBytesOf(sceneFile, hash);
    for (const std::filesystem::path& mesh : meshFiles) hashBytesOf(mesh, hash);
    return formatHash(hash);
}

}  // namespace penumbra
