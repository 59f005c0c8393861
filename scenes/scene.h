// The scene as plain data, exactly as the user described it: what the loaders produce and what
// the traversal backends and the renderer consume. Geometry is already in world space.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cameras/camera.h"
#include "core/motion.h"
#include "core/rgb.h"
#include "core/sampler.h"
#include "core/vec.h"

namespace penumbra {

struct CameraDesc {
    Vec3f lookFrom{0.0f, 0.0f, 0.0f};
    Vec3f lookAt{0.0f, 0.0f, -1.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    float verticalFovDegrees = 40.0f;
    float apertureRadius = 0.0f;  // lens radius in scene units; 0 is a pinhole
    float focusDistance = 0.0f;   // along the view direction; 0 means |lookAt - lookFrom|
    int apertureBlades = 0;       // 0: circular aperture; >= 3: regular polygon
    float apertureRotationDegrees = 0.0f;
    float shutterOpen = 0.0f;
    float shutterClose = 0.0f;
    // Camera motion: empty, or >= 2 poses evenly spaced over the shutter, interpolated linearly;
    // they replace lookFrom / lookAt / up.
    std::vector<CameraPose> motion;
};

enum class FilterKind : uint8_t { Box, Tent };

struct FilmDesc {
    int width = 512;
    int height = 512;
    int samplesPerPixel = 16;
    FilterKind filter = FilterKind::Tent;
    float filterRadius = 1.0f;  // in pixels: box covers [-r, r]^2, tent falls to 0 at r
};

struct IntegratorDesc {
    // Number of scattering events a path may have (pbrt's convention): 0 shows only emitters seen
    // directly, 1 adds direct lighting, and so on.
    int maxDepth = 64;
    // Russian roulette starts at this bounce; before it every path survives.
    int rouletteStartDepth = 3;
};

struct RenderSettings {
    SamplerKind sampler = SamplerKind::Stratified;
    uint64_t seed = 0;
    // Watertight traversal with Embree (its robust mode): no ray slips through an edge shared by
    // two triangles. Off, Embree uses its faster default traversal (as Embree's own tutorials do),
    // which rarely lets a ray through such an edge. Our BVH is always watertight.
    bool watertight = true;
    // Canonical hits: Embree's hits are recomputed with our BVH's triangle and sphere tests
    // (renderer/surface_interaction.h), so that renders with either backend are bit-identical
    // wherever both find the same primitives. Off, Embree's own t and barycentrics are shaded.
    bool canonicalHits = true;
};

enum class MaterialKind : uint8_t { Lambert, Phong, Dielectric, ThinDielectric, Mirror, Conductor };

enum class FresnelKind : uint8_t { Exact, Schlick };

// One material as the scene file gives it (scenes/README.md); only the fields of its kind matter.
struct MaterialDesc {
    std::string name;
    MaterialKind kind = MaterialKind::Lambert;
    Rgb albedo{0.5f, 0.5f, 0.5f};  // Lambert reflectance, each channel in [0, 1]
    bool twoSided = true;          // Lambert, Phong, mirror, conductor: false makes the back black
    // Phong: diffuse + specular <= 1 per channel; exponent >= 0.
    Rgb diffuse{0.5f, 0.5f, 0.5f};
    Rgb specular{0.0f, 0.0f, 0.0f};
    float exponent = 10.0f;
    // Dielectric and thin dielectric: interior index over exterior index (> 0), Fresnel model.
    float eta = 1.5f;
    FresnelKind fresnel = FresnelKind::Exact;
    Rgb absorption{0.0f, 0.0f, 0.0f};  // dielectric: sigma_a = -ln(color) / distance, per unit length
    Rgb tint{1.0f, 1.0f, 1.0f};        // mirror reflectance, each channel in [0, 1]
    // Conductor: complex index eta + i k per channel (conductorEta > 0, k >= 0).
    Rgb conductorEta{1.0f, 1.0f, 1.0f};
    Rgb k{0.0f, 0.0f, 0.0f};
};

// Emission turns any shape into an area light with constant radiance.
struct Emission {
    Rgb radiance;            // black: the shape does not emit
    bool twoSided = false;   // one-sided lights emit on the front side only
    bool emits() const { return !radiance.isBlack(); }
};

// Motion: times are shutter fractions (0 = shutter open, 1 = closed), the same as Ray::time.
// A mesh or sphere with a moving `motion` transform keeps its geometry in object space and is
// placed in the world by motion.at(time); otherwise its geometry is in world space.
struct TriangleMesh {
    std::string name;              // for messages: the scene's JSON pointer or the file name
    std::vector<Vec3f> positions;  // world space, or object space when `motion` moves; the first
                                   // deformation key when there are several
    std::vector<Vec3f> normals;    // optional, per vertex, world space, unit length
    std::vector<Vec2f> uvs;        // optional, per vertex
    std::vector<uint32_t> indices; // three per triangle; front face is counter-clockwise,
                                   // i.e. its normal is cross(p1 - p0, p2 - p0)
    uint32_t material = 0;         // index into Scene::materials
    Emission emission;
    // Deformation: empty, or >= 2 arrays of positions (the first equal to `positions`), evenly
    // spaced over the shutter and interpolated linearly per vertex.
    std::vector<std::vector<Vec3f>> positionKeys;
    MotionTransform motion;

    size_t triangleCount() const { return indices.size() / 3; }
    bool deforms() const { return positionKeys.size() >= 2; }
};

struct Sphere {
    std::string name;
    Vec3f center;
    float radius = 1.0f;  // > 0; the front side is the outside
    uint32_t material = 0;
    Emission emission;
    MotionTransform motion;  // when it moves, center and radius are in object space
};

struct PointLight {
    Vec3f position;
    Rgb intensity;  // radiant intensity, W/sr per channel
};

// Light from a very distant source arriving along one direction (the sun): hard shadows.
struct DirectionalLight {
    Vec3f direction;  // unit, the direction the light travels
    Rgb irradiance;   // W/m^2 per channel on a surface facing the light
};

struct Scene {
    std::filesystem::path sourcePath;  // the scene file, for messages and metadata
    // The mesh files the scene names, in the order it names them (a file named twice is listed
    // twice): with the scene file, what the scene hash in a film's metadata covers.
    std::vector<std::filesystem::path> meshFiles;
    CameraDesc camera;
    FilmDesc film;
    IntegratorDesc integrator;
    RenderSettings settings;
    std::vector<MaterialDesc> materials;
    std::vector<TriangleMesh> meshes;
    std::vector<Sphere> spheres;
    std::vector<PointLight> pointLights;
    std::vector<DirectionalLight> directionalLights;
    Rgb background;  // constant radiance arriving from every direction that escapes the scene

    // Whether any shape moves or deforms over the shutter or the camera moves: otherwise a ray's
    // time changes nothing.
    bool hasMotion() const {
        for (const TriangleMesh& mesh : meshes)
            if (mesh.deforms() || mesh.motion.moves()) return true;
        for (const Sphere& sphere : spheres)
            if (sphere.motion.moves()) return true;
        return !camera.motion.empty();
    }
};

}  // namespace penumbra
