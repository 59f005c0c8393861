// The pbrt-v4 reader over several files (formats/pbrt): Include and Import graphs, fan-out, cycles,
// object definitions and attribute blocks that span files. One input is split at each line "%%"
// into up to eight files, a.pbrt to h.pbrt, written to a folder of this process's own; a.pbrt is
// the scene, and Include "b.pbrt" (or Import) names another. A finding reproduces as any other:
// build-fuzz/fuzz/pbrt_include_fuzzer FILE splits it the same way.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "formats/pbrt/pbrt_reader.h"
#include "fuzz/fuzz_input.h"

namespace {

namespace fs = std::filesystem;

constexpr int kMaxFiles = 8;

// The folder of the scene's files, removed at exit.
class SceneFolder {
public:
    SceneFolder() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/penumbra-fuzz-include.XXXXXX";
        if (!mkdtemp(pattern.data())) std::abort();
        folder_ = pattern;
    }
    ~SceneFolder() {
        std::error_code ec;
        fs::remove_all(folder_, ec);
    }
    SceneFolder(const SceneFolder&) = delete;
    SceneFolder& operator=(const SceneFolder&) = delete;

    // Writes the parts of `text` (separated by lines "%%") as a.pbrt, b.pbrt, ...; the files of the
    // previous input that this one does not have are removed. Returns the path of a.pbrt.
    fs::path write(std::string_view text) {
        int files = 0;
        while (files < kMaxFiles) {
            size_t end = text.find("\n%%\n");
            const bool last = end == std::string_view::npos || files + 1 == kMaxFiles;
            if (last) end = text.size();
            writeFile(nameOf(files++), text.substr(0, end));
            if (last) break;
            text.remove_prefix(end + 4);
        }
        for (int i = files; i < kMaxFiles; ++i) {
            std::error_code ec;
            fs::remove(folder_ / nameOf(i), ec);
        }
        return folder_ / nameOf(0);
    }

private:
    static std::string nameOf(int i) { return std::string(1, char('a' + i)) + ".pbrt"; }
    void writeFile(const std::string& name, std::string_view bytes) {
        FILE* f = std::fopen((folder_ / name).c_str(), "wb");
        if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0)
            std::abort();
    }

    fs::path folder_;
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    penumbra::fuzz::loadTexturePluginBeforeFuzzing();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static SceneFolder folder;
    const fs::path scene = folder.write(penumbra::fuzz::asText(data, size));
    return penumbra::fuzz::expectReadOrInputError([&] {
        const penumbra::pbrt::PbrtConversion conversion = penumbra::pbrt::convertPbrtFile(scene);
        penumbra::pbrt::buildPbrtScene(conversion, scene);
    });
}
