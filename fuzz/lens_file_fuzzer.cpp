// Lens description files (parseLensFile), then the surfaces read: between 1 and kMaxLensSurfaces,
// every number finite, thicknesses and indices >= 0, diameters > 0. A file breaking that aborts
// (a finding like a crash).
#include <cmath>
#include <cstdlib>

#include "cameras/lens_file.h"
#include "fuzz/fuzz_input.h"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    return fuzz::expectReadOrInputError([&] {
        const auto surfaces = parseLensFile(fuzz::asText(data, size), "fuzz.dat");
        check(!surfaces.empty() && surfaces.size() <= kMaxLensSurfaces);
        for (const LensSurface& s : surfaces) {
            check(std::isfinite(s.curvatureRadius) && std::isfinite(s.thickness) && std::isfinite(s.eta) &&
                  std::isfinite(s.apertureDiameter));
            check(s.thickness >= 0.0f && s.eta >= 0.0f && s.apertureDiameter > 0.0f);
        }
    });
}
