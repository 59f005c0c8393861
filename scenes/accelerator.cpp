// The one place that knows every traversal backend.
#include "scenes/accelerator.h"

#include "scenes/bvh_accelerator.h"
#include "scenes/embree_accelerator.h"

namespace penumbra {

std::unique_ptr<Accelerator> makeAccelerator(AcceleratorKind kind, const Scene& scene) {
    switch (kind) {
        case AcceleratorKind::Embree: return std::make_unique<EmbreeAccelerator>(scene);
        case AcceleratorKind::Bvh: return std::make_unique<BvhAccelerator>(scene);
    }
    return nullptr;
}

}  // namespace penumbra
