// What the fuzz targets share: the contract they check and a scratch file for readers that take
// a path.
//
// The contract of every reader under test: any input either reads or throws InputError (which
// `penumbra` prints as a clear error). Any other exception escapes the target, and libFuzzer
// reports it as a crash, like a sanitizer report, a PENUMBRA_CHECK failure, a hang or an
// allocation beyond the run's memory limit.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/error.h"
#include "textures/texture_plugin_loader.h"

namespace penumbra::fuzz {

inline std::string_view asText(const uint8_t* data, size_t size) {
    return std::string_view(reinterpret_cast<const char*>(data), size);
}

// Runs `read` and swallows the InputError that bad input is allowed to give.
template <typename Read>
int expectReadOrInputError(Read read) {
    try {
        read();
    } catch (const InputError&) {
    }
    return 0;
}

// Loads the texture plugin (OpenImageIO and the libraries under it) before the first input, from
// LLVMFuzzerInitialize, for the targets whose inputs can name an image texture. Its one-time
// dlopen is not the reader's work, yet timed as part of the first input that needs it: on a loaded
// machine it took over the 10 s a single input may take, a timeout on a seed that reads in 1 s.
inline void loadTexturePluginBeforeFuzzing() {
    try {
        (void)texturePlugin();
    } catch (const InputError&) {
        // No plugin here: the inputs naming a texture get this error, as in penumbra.
    }
}

// A file in a folder of this process's own (under $TMPDIR, else /tmp), rewritten for each input:
// for the readers whose only entry point is a path (films, gzip-compressed meshes). The folder is
// removed at exit.
class ScratchFile {
public:
    explicit ScratchFile(const std::string& name) {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/penumbra-fuzz.XXXXXX";
        if (!mkdtemp(pattern.data())) std::abort();
        folder_ = pattern;
        path_ = folder_ / name;
    }
    ~ScratchFile() {
        std::error_code ec;
        std::filesystem::remove_all(folder_, ec);
    }
    ScratchFile(const ScratchFile&) = delete;
    ScratchFile& operator=(const ScratchFile&) = delete;

    const std::filesystem::path& folder() const { return folder_; }

    // Replaces the file's contents with `bytes`; returns its path.
    const std::filesystem::path& write(const uint8_t* bytes, size_t size) {
        FILE* f = std::fopen(path_.c_str(), "wb");
        if (!f || std::fwrite(bytes, 1, size, f) != size || std::fclose(f) != 0) std::abort();
        return path_;
    }

private:
    std::filesystem::path folder_, path_;
};

}  // namespace penumbra::fuzz
