#include "core/sampler.h"

namespace penumbra {

std::string_view samplerKindName(SamplerKind kind) {
    switch (kind) {
        case SamplerKind::Stratified:
            return "stratified";
        case SamplerKind::Independent:
            return "independent";
    }
    return "unknown";
}

}  // namespace penumbra
