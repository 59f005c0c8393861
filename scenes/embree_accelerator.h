// The Embree backend: every Embree call of penumbra lives in embree_accelerator.cpp.
#pragma once

#include <embree3/rtcore.h>

#include <vector>

#include "scenes/accelerator.h"

namespace penumbra {

struct EmbreeOptions {
    // RTC_SCENE_FLAG_ROBUST: watertight traversal, no ray slips through a shared edge (see
    // RenderSettings::watertight). Off, traversal is about a quarter faster.
    bool robust = true;
};

class EmbreeAccelerator final : public Accelerator {
public:
    explicit EmbreeAccelerator(const Scene& scene, EmbreeOptions options = {});
    ~EmbreeAccelerator() override;
    EmbreeAccelerator(const EmbreeAccelerator&) = delete;
    EmbreeAccelerator& operator=(const EmbreeAccelerator&) = delete;

    std::string_view name() const override { return "embree"; }
    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;

    // Up to kPacketSize coherent rays (a pixel's camera rays) traced together with Embree's packet
    // kernel, which traverses once for all of them; found[i] and hits[i] as intersect() gives them.
    // The packet kernel rounds like itself, not necessarily like the single-ray one, so a ray
    // traced here must always be traced here (the render loop does so for every camera ray).
    static constexpr int kPacketSize = 8;
    void intersectPacket(const Ray* rays, int count, Hit* hits, bool* found) const;

private:
    // Scene ids from Embree's (see accelerator.h).
    void setIds(unsigned geomId, unsigned primId, Hit& hit) const;

    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<RTCScene> instancedScenes_;  // one per moving object, released with the backend
    uint32_t sphereGeomId_ = 0;              // == meshes.size(): all static spheres
    std::vector<uint32_t> movingSphereOfGeomId_;  // geomId - sphereGeomId_ - 1 -> sphere index
};

}  // namespace penumbra
