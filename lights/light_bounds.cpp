#include "lights/light_bounds.h"

#include <algorithm>

namespace penumbra {

void LightBoundsBatch::set(size_t i, const LightBounds& b) {
    centerX_[i] = b.center.x;
    centerY_[i] = b.center.y;
    centerZ_[i] = b.center.z;
    radius_[i] = b.radius;
    radiusSquared_[i] = b.radius * b.radius;
    axisX_[i] = b.axis.x;
    axisY_[i] = b.axis.y;
    axisZ_[i] = b.axis.z;
    phi_[i] = b.phi;
    cosThetaO_[i] = b.cosThetaO;
    sinThetaO_[i] = safeSqrt(1.0f - b.cosThetaO * b.cosThetaO);
    cosThetaE_[i] = b.cosThetaE;
    twoSided_[i] = b.twoSided ? 1.0f : 0.0f;
    used_ = std::max(used_, (i / kLanes + 1) * kLanes);
}

// Vectorized by GCC under `omp simd` (-fopenmp-simd; bench/README.md, "Speed tricks").
void LightBoundsBatch::importances(Vec3f p, Vec3f n, float* out) const {
#pragma omp simd
    for (size_t i = 0; i < used_; ++i)
        out[i] = detail::lightImportance(p.x, p.y, p.z, n.x, n.y, n.z, centerX_[i], centerY_[i], centerZ_[i],
                                         radius_[i], radiusSquared_[i], axisX_[i], axisY_[i], axisZ_[i],
                                         phi_[i], cosThetaO_[i], sinThetaO_[i], cosThetaE_[i], twoSided_[i]);
}

}  // namespace penumbra
