// The pbrt-v4 reader (formats/pbrt): tokenizer, typed parameter lists, directives, the mapping to
// penumbra's format and the native loader that builds the result. The scene "lives" in
// tests/data/pbrt/scenes, so Include, Import and mesh names can reach the fixture files there.
#include "formats/pbrt/pbrt_reader.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    penumbra::fuzz::loadTexturePluginBeforeFuzzing();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::filesystem::path scene =
        std::filesystem::path(PENUMBRA_TEST_DATA_DIR) / "pbrt/scenes/fuzz.pbrt";
    return penumbra::fuzz::expectReadOrInputError([&] {
        const penumbra::pbrt::PbrtConversion conversion =
            penumbra::pbrt::convertPbrtText(penumbra::fuzz::asText(data, size), scene);
        penumbra::pbrt::buildPbrtScene(conversion, scene);
    });
}
