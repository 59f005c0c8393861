// The scene as the user described it: what the loaders produce and what the traversal backends
// and the renderer consume. Its members are the runtime values themselves (materials, camera
// parameters, lights), not descriptions of them to be converted later.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cameras/camera.h"
#include "cameras/sensor_response.h"
#include "core/adaptive_schedule.h"
#include "core/rgb.h"
#include "core/sampler.h"
#include "geometry/scene_geometry.h"
#include "lights/environment_light.h"
#include "lights/light.h"
#include "lights/light_sampler.h"
#include "materials/material.h"
#include "media/medium.h"

namespace penumbra {

enum class FilterKind : uint8_t { Box, Tent };

struct FilmSettings {
    int width = 512;
    int height = 512;
    int samplesPerPixel = 16;
    FilterKind filter = FilterKind::Tent;
    float filterRadius = 1.0f;  // in pixels: box covers [-r, r]^2, tent falls to 0 at r
    // Adaptive sampling (film.adaptive, --adaptive): pixels stop before samplesPerPixel once
    // converged. None: every pixel gets samplesPerPixel samples.
    std::optional<AdaptiveSettings> adaptive{};
    // film.crop_window (pbrt-v4's cropwindow): only the pixels in these fractions x0, x1, y0, y1
    // of the image are rendered (x0 < x1, y0 < y1, in [0, 1]); --crop takes its place.
    std::optional<std::array<float, 4>> cropWindow{};
    // film.sensor (pbrt-v4's iso, exposure time and white balance): what each sample's radiance
    // becomes on the film (cameras/sensor_response.h). None: the radiance itself.
    std::optional<SensorResponse> sensor{};
};

// How the integrator finds light at each vertex: both strategies weighted by multiple importance
// sampling (Veach's power heuristic), or one alone, for studies of what MIS buys (`penumbra
// converge --strategy`). BSDF sampling alone never finds point or directional lights.
enum class LightStrategy : uint8_t { Mis, Bsdf, Light };
constexpr std::string_view lightStrategyName(LightStrategy strategy) {
    return strategy == LightStrategy::Mis ? "mis" : strategy == LightStrategy::Bsdf ? "bsdf" : "light";
}

struct IntegratorSettings {
    // Number of scattering events a path may have (pbrt's convention): 0 shows only emitters seen
    // directly, 1 adds direct lighting, and so on.
    int maxDepth = 64;
    // Russian roulette starts at this bounce; before it every path survives.
    int rouletteStartDepth = 3;
    LightStrategy strategy = LightStrategy::Mis;
    LightSampler lightSampler = LightSampler::Bvh;
};

struct RenderSettings {
    SamplerKind sampler = SamplerKind::Stratified;
    uint64_t seed = 0;
    // Watertight traversal with Embree (its robust mode): no ray slips through an edge shared by
    // two triangles. Off, Embree uses its faster default traversal (as Embree's own tutorials do),
    // which rarely lets a ray through such an edge. Our BVH is always watertight.
    bool watertight = true;
    // Canonical hits: Embree's hits are recomputed with our BVH's triangle and sphere tests
    // (geometry/surface_interaction.h), so that renders with either backend are bit-identical
    // wherever both find the same primitives. Off, Embree's own t and barycentrics are shaded.
    bool canonicalHits = true;
};

// Geometry is in world space (moving shapes: in object space, placed by their motion; prototypes:
// in their own space, placed by their instances). Every
// member holds the runtime value the renderer uses; the loaders build them directly.
struct Scene : SceneGeometry {
    std::filesystem::path sourcePath;  // the scene file, for messages and metadata
    // The mesh files the scene names, in the order it names them (a file named twice is listed
    // twice): with the scene file, what the scene hash in a film's metadata covers.
    std::vector<std::filesystem::path> meshFiles;
    // The files the scene file includes (pbrt's Include and Import) and a patch applied to it
    // (scene_file.h), also covered by the hash.
    std::vector<std::filesystem::path> includedFiles;
    CameraParams camera;
    FilmSettings film;
    IntegratorSettings integrator;
    RenderSettings settings;
    std::vector<Material> materials;
    std::vector<std::string> materialNames;  // materialNames[i] names materials[i]
    // The lights the scene names besides its emitting shapes and its environment (point, spot,
    // goniometric, directional), in the file's order.
    std::vector<LightModel> lights;
    // Participating media (media/medium.h), which shapes bound (their MediumInterface) and the
    // camera may sit in; mediumNames[i] names media[i].
    std::vector<MediumModel> media;
    std::vector<std::string> mediumNames;
    // Media from this index on fill subsurface materials (scenes/material_interior.h): the file's
    // own media come first.
    uint32_t firstMaterialInterior = MediumInterface::kVacuum;
    uint32_t cameraMedium = MediumInterface::kVacuum;
    // Light arriving along every direction that escapes the scene: black, a constant (the scene
    // file's "background") or an image (its "environment").
    EnvironmentLight environment;

    // Whether any shape moves or deforms over the shutter or the camera moves: otherwise a ray's
    // time changes nothing.
    bool hasMotion() const { return shapesMove() || !camera.motion.empty(); }
    // Whether `medium` fills a subsurface material: paths in it are random walks, which the
    // integrator counts and lights apart.
    bool isMaterialInterior(uint32_t medium) const {
        return medium != MediumInterface::kVacuum && medium >= firstMaterialInterior;
    }
    // Whether paths may travel through media or cross medium boundaries: the scene is then
    // rendered by the volumetric integrator (renderer/volumetric_path_integrator.h).
    bool hasMedia() const {
        if (!media.empty()) return true;
        for (const Material& material : materials)
            if (material.isInterface()) return true;
        return false;
    }
};

}  // namespace penumbra
