// Wavefront OBJ import (importObj, and importObjPolygons for subdivision surfaces): our validator,
// then tinyobjloader, then the mesh checks.
#include "fuzz/fuzz_input.h"
#include "scenes/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return penumbra::fuzz::expectReadOrInputError(
               [&] { penumbra::importObj(penumbra::fuzz::asText(data, size), "fuzz.obj"); }) |
           penumbra::fuzz::expectReadOrInputError(
               [&] { penumbra::importObjPolygons(penumbra::fuzz::asText(data, size), "fuzz.obj"); });
}
