// The JSON scene reader (parseScene): syntax, keys, types, ranges, materials, and the mesh files a
// scene names. The scene "lives" in tests/data/scenes, so the names of its fixture meshes
// (meshes/square.obj, meshes/square_binary_le.ply, meshes/square.ply.gz, ...) load real files.
#include "fuzz/fuzz_input.h"
#include "scenes/scene_loader.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    penumbra::fuzz::loadTexturePluginBeforeFuzzing();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::filesystem::path scene =
        std::filesystem::path(PENUMBRA_TEST_DATA_DIR) / "scenes/fuzz.json";
    return penumbra::fuzz::expectReadOrInputError(
        [&] { penumbra::parseScene(penumbra::fuzz::asText(data, size), scene); });
}
