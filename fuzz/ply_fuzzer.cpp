// PLY import, ASCII and binary (importPly: the header validator, then our reader that checks the body
// as it reads it), and gzip-compressed PLY: an input that starts with the gzip magic bytes is written to a
// .ply.gz file and read through importMesh (zlib, the inflation limit, then the same PLY reader).
#include "fuzz/fuzz_input.h"
#include "scenes/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    static fuzz::ScratchFile gzipFile("fuzz.ply.gz");
    // Far below the 4 GiB default, so that a small input inflating to a large one ends as an
    // InputError rather than at the fuzzer's memory limit (the limit's check is what is tested).
    constexpr uint64_t kMaxInflatedBytes = uint64_t(64) << 20;
    const bool gzip = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
    return fuzz::expectReadOrInputError([&] {
               if (gzip)
                   importMesh(gzipFile.write(data, size), kMaxInflatedBytes);
               else
                   importPly(fuzz::asText(data, size), "fuzz.ply");
           }) |
           fuzz::expectReadOrInputError([&] {
               if (!gzip) importPlyPolygons(fuzz::asText(data, size), "fuzz.ply");
           });
}
