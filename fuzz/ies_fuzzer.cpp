// IES LM-63 photometric files (readIesProfileText), then the profile read: its intensity in a few
// directions and at the table's own angles is finite, 0 or more and at most maxCandela(), and its
// flux is finite and 0 or more. A profile breaking that aborts (a finding like a crash).
#include <cmath>
#include <cstdlib>

#include "fuzz/fuzz_input.h"
#include "lights/ies_profile.h"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

void checkIntensity(const penumbra::IesProfile& profile, float candela) {
    check(std::isfinite(candela) && candela >= 0 && candela <= profile.maxCandela());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    return fuzz::expectReadOrInputError([&] {
        const IesProfile profile = readIesProfileText(fuzz::asText(data, size), "fuzz.ies");
        check(std::isfinite(profile.totalFlux()) && profile.totalFlux() >= 0);
        for (const Vec3f d : {Vec3f(0, 0, 1), Vec3f(0, 0, -1), Vec3f(1, 0, 0), Vec3f(-1, 1, 0.5f),
                              Vec3f(0.3f, -0.2f, -0.9f), Vec3f(-0.5f, -0.5f, 0)})
            checkIntensity(profile, profile.intensity(d));
        const auto& v = profile.verticalAngles();
        const auto& h = profile.horizontalAngles();
        for (size_t i = 0; i < v.size(); i += 1 + v.size() / 8)
            for (size_t j = 0; j < h.size(); j += 1 + h.size() / 8) {
                checkIntensity(profile, profile.candelaAt(v[i], h[j]));
                // Exactly the table's value at its angles, but for the last (the first's, plus 360)
                // and mirrored angles that rounded to one.
                const bool distinct = j + 1 < h.size() && h[j + 1] != h[j] && (j == 0 || h[j - 1] != h[j]);
                if (distinct) check(profile.candelaAt(v[i], h[j]) == profile.value(i, j));
            }
    });
}
