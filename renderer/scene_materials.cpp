#include "renderer/scene_materials.h"

namespace penumbra {

std::vector<Material> buildMaterials(const Scene& scene) {
    std::vector<Material> materials;
    materials.reserve(scene.materials.size());
    for (const MaterialDesc& desc : scene.materials) {
        Material m;
        m.twoSided = desc.twoSided;
        const FresnelModel fresnel = desc.fresnel == FresnelKind::Schlick ? FresnelModel::Schlick : FresnelModel::Exact;
        switch (desc.kind) {
            case MaterialKind::Lambert:
                m.type = MaterialType::Lambert;
                m.lambert.albedo = desc.albedo;
                break;
            case MaterialKind::Phong:
                m.type = MaterialType::Phong;
                m.phong.kd = desc.diffuse;
                m.phong.ks = desc.specular;
                m.phong.exponent = desc.exponent;
                break;
            case MaterialKind::Dielectric:
                m.type = MaterialType::Dielectric;
                m.dielectric.eta = desc.eta;
                m.dielectric.fresnel = fresnel;
                m.dielectric.absorption = desc.absorption;
                break;
            case MaterialKind::ThinDielectric:
                m.type = MaterialType::ThinDielectric;
                m.thinDielectric.eta = desc.eta;
                m.thinDielectric.fresnel = fresnel;
                break;
            case MaterialKind::Mirror:
                m.type = MaterialType::Mirror;
                m.mirror.tint = desc.tint;
                break;
            case MaterialKind::Conductor:
                m.type = MaterialType::Conductor;
                m.conductor.eta = desc.conductorEta;
                m.conductor.k = desc.k;
                break;
        }
        materials.push_back(m);
    }
    return materials;
}

}  // namespace penumbra
