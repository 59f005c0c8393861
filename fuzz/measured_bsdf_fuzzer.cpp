// Measured BRDFs of the RGL format (parseMeasuredBsdf: the tensor file, then the tables), then the
// BRDF read: evaluated, its pdf taken and sampled for a few directions, every value finite and the
// densities non-negative. A file breaking that aborts (a finding like a crash).
#include <cmath>
#include <cstdlib>

#include "fuzz/fuzz_input.h"
#include "materials/measured_bsdf_reader.h"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    return fuzz::expectReadOrInputError([&] {
        const MeasuredBsdf bsdf{parseMeasuredBsdf(fuzz::asText(data, size), "fuzz.bsdf")};
        const Vec3f directions[] = {
            {0.0f, 0.0f, 1.0f}, {0.6f, 0.0f, 0.8f}, {-0.28f, -0.96f, 0.0f}, {0.0f, 0.6f, -0.8f}};
        for (const Vec3f& wo : directions) {
            for (const Vec3f& wi : directions) {
                const Rgb f = bsdf.eval(wo, wi, true);
                const float pdf = bsdf.pdf(wo, wi, true);
                check(f.isFinite() && f.minComponent() >= 0.0f && std::isfinite(pdf) && pdf >= 0.0f);
            }
            for (const Vec2f u : {Vec2f{0.1f, 0.2f}, Vec2f{0.5f, 0.5f}, Vec2f{0.0f, 0.99999994f}})
                if (const auto s = bsdf.sample(wo, 0.5f, u, true))
                    check(s->weight.isFinite() && s->pdf > 0.0f && std::isfinite(s->pdf) &&
                          std::isfinite(s->wi.z));
        }
    });
}
