#include "scenes/scene_loader.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "core/frame.h"
#include "core/motion.h"
#include "core/transform.h"
#include "scenes/json_reader.h"
#include "scenes/mesh_import.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// Larger films are surely typos, and this keeps width * height far from overflowing.
constexpr int64_t kMaxResolution = 1 << 16;
constexpr int64_t kMaxInt = std::numeric_limits<int32_t>::max();

// The look_from / look_at / up members of `value` (whose keys the caller has checked).
CameraPose readCameraPose(const JsonValue& value, const CameraPose& defaults) {
    CameraPose pose = defaults;
    if (auto v = value.member("look_from")) pose.lookFrom = v->vec3();
    if (auto v = value.member("look_at")) pose.lookAt = v->vec3();
    if (auto v = value.member("up")) pose.up = v->vec3();
    if (!Transform::lookAt(pose.lookFrom, pose.lookAt, pose.up))
        value.fail(
            "look_from and look_at must differ, and up must be non-zero and not parallel to the "
            "viewing direction");
    return pose;
}

CameraDesc readCamera(const JsonValue& value) {
    const JsonObject object(value, {"look_from", "look_at", "up", "fov", "aperture_radius", "f_number", "focal_length",
                                    "aperture_blades", "aperture_rotation", "focus_distance", "focus_on", "shutter",
                                    "motion"});
    CameraDesc camera;
    const CameraPose pose = readCameraPose(value, {camera.lookFrom, camera.lookAt, camera.up});
    camera.lookFrom = pose.lookFrom;
    camera.lookAt = pose.lookAt;
    camera.up = pose.up;
    if (auto v = object.get("fov")) {
        if (!v->json().is_number() || !(v->number() > 0.0f && v->number() < 180.0f))
            v->failExpected("a vertical field of view in degrees, greater than 0 and less than 180");
        camera.verticalFovDegrees = v->number();
    }

    // The aperture: a lens radius, or an f-number with the lens's focal length (radius = f / 2N).
    const auto fNumber = object.get("f_number"), focalLength = object.get("focal_length");
    if (auto v = object.get("aperture_radius")) {
        if (fNumber) fNumber->fail("give either aperture_radius or f_number with focal_length, not both");
        camera.apertureRadius = v->numberAtLeast(0.0f);
    } else if (fNumber || focalLength) {
        if (!fNumber) value.fail("focal_length needs f_number to define the aperture");
        if (!focalLength) value.fail("f_number needs focal_length (in scene units) to define the aperture");
        camera.apertureRadius = focalLength->numberAbove(0.0f) / (2.0f * fNumber->numberAbove(0.0f));
    }
    if (auto v = object.get("aperture_blades")) {
        camera.apertureBlades = int(v->integer(0, 64));
        if (camera.apertureBlades == 1 || camera.apertureBlades == 2)
            v->failExpected("0 (a round aperture) or 3 to 64 blades");
    }
    if (auto v = object.get("aperture_rotation")) camera.apertureRotationDegrees = v->number();

    // Focus: a distance along the view direction, or a point to focus on; by default look_at.
    if (auto v = object.get("focus_distance")) {
        if (object.get("focus_on")) v->fail("give either focus_distance or focus_on, not both");
        camera.focusDistance = v->numberAbove(0.0f);
    } else if (auto v = object.get("focus_on")) {
        const Vec3f view = normalize(camera.lookAt - camera.lookFrom);
        camera.focusDistance = dot(v->vec3() - camera.lookFrom, view);
        if (!(camera.focusDistance > 0.0f)) v->fail("the point to focus on must lie in front of the camera");
    }

    if (auto v = object.get("shutter")) {
        if (!v->json().is_array() || v->json().size() != 2)
            v->failExpected("an array [open, close] of 2 numbers");
        camera.shutterOpen = v->element(0).number();
        camera.shutterClose = v->element(1).number();
        if (camera.shutterClose < camera.shutterOpen) v->failExpected("[open, close] with close >= open");
    }
    if (auto v = object.get("motion")) {
        if (v->arraySize() < 2) v->failExpected("an array of at least 2 camera poses, evenly spaced over the shutter");
        // Each pose starts from the camera's own and changes what it names.
        for (const JsonValue& poseValue : v->elements()) {
            const JsonObject poseObject(poseValue, {"look_from", "look_at", "up"});
            camera.motion.push_back(readCameraPose(poseValue, pose));
        }
    }
    return camera;
}

FilmDesc readFilm(const JsonValue& value) {
    const JsonObject object(value, {"resolution", "spp", "filter"});
    FilmDesc film;
    if (auto v = object.get("resolution")) {
        if (!v->json().is_array() || v->json().size() != 2)
            v->failExpected("an array [width, height] of 2 integers");
        film.width = int(v->element(0).integer(1, kMaxResolution));
        film.height = int(v->element(1).integer(1, kMaxResolution));
    }
    if (auto v = object.get("spp")) film.samplesPerPixel = int(v->integer(1, kMaxInt));
    if (auto v = object.get("filter")) {
        const JsonObject filter(*v, {"type", "radius"});
        if (auto type = filter.get("type"))
            film.filter = type->choice({"box", "tent"}) == 0 ? FilterKind::Box : FilterKind::Tent;
        if (auto radius = filter.get("radius")) film.filterRadius = radius->numberAbove(0.0f);
    }
    return film;
}

IntegratorDesc readIntegrator(const JsonValue& value) {
    const JsonObject object(value, {"max_depth", "roulette_start"});
    IntegratorDesc integrator;
    if (auto v = object.get("max_depth")) integrator.maxDepth = int(v->integer(0, kMaxInt));
    if (auto v = object.get("roulette_start")) integrator.rouletteStartDepth = int(v->integer(0, kMaxInt));
    return integrator;
}

RenderSettings readRender(const JsonValue& value) {
    const JsonObject object(value, {"sampler", "seed", "watertight", "canonical_hits"});
    RenderSettings settings;
    if (auto v = object.get("sampler"))
        settings.sampler = v->choice({"stratified", "independent"}) == 0 ? SamplerKind::Stratified
                                                                         : SamplerKind::Independent;
    if (auto v = object.get("seed")) settings.seed = v->unsignedInteger();
    if (auto v = object.get("watertight")) settings.watertight = v->boolean();
    if (auto v = object.get("canonical_hits")) settings.canonicalHits = v->boolean();
    return settings;
}

FresnelKind readFresnel(const JsonValue& value) {
    return value.choice({"exact", "schlick"}) == 0 ? FresnelKind::Exact : FresnelKind::Schlick;
}

// "absorption": {"color": c, "distance": d}: light keeps the fraction c (per channel, in (0, 1])
// after travelling d inside, so sigma_a = -ln(c) / d.
Rgb readAbsorption(const JsonValue& value) {
    const JsonObject object(value, {"color", "distance"});
    const JsonValue colorValue = object.require("color");
    const Rgb color = colorValue.rgb(0.0f, 1.0f);
    for (int c = 0; c < 3; ++c)
        if (!(color[c] > 0.0f))
            colorValue.failExpected(
                "a transmittance in (0, 1] per channel (0 would absorb everything at any distance)");
    const float distance = object.require("distance").numberAbove(0.0f);
    return {-std::log(color.r) / distance, -std::log(color.g) / distance, -std::log(color.b) / distance};
}

MaterialDesc readMaterial(const std::string& name, const JsonValue& material) {
    MaterialDesc desc;
    desc.name = name;
    const size_t type = material.requiredMember("type").choice(
        {"lambert", "phong", "dielectric", "thin_dielectric", "mirror", "conductor"});
    switch (type) {
        case 0: {
            const JsonObject object(material, {"type", "albedo", "two_sided"});
            desc.kind = MaterialKind::Lambert;
            if (auto v = object.get("albedo")) desc.albedo = v->rgb(0.0f, 1.0f);
            if (auto v = object.get("two_sided")) desc.twoSided = v->boolean();
            break;
        }
        case 1: {
            const JsonObject object(material, {"type", "diffuse", "specular", "exponent", "two_sided"});
            desc.kind = MaterialKind::Phong;
            if (auto v = object.get("diffuse")) desc.diffuse = v->rgb(0.0f, 1.0f);
            if (auto v = object.get("exponent")) desc.exponent = v->numberAtLeast(0.0f);
            if (auto v = object.get("two_sided")) desc.twoSided = v->boolean();
            if (auto v = object.get("specular")) {
                desc.specular = v->rgb(0.0f, 1.0f);
                // diffuse alone is at most 1, so a sum above 1 always involves a given specular.
                static constexpr const char* kChannels[] = {"red", "green", "blue"};
                for (int c = 0; c < 3; ++c)
                    if (desc.diffuse[c] + desc.specular[c] > 1.0f)
                        v->fail(fmt::format(
                            "diffuse + specular must not exceed 1 in any channel (energy conservation), but "
                            "the {} channel has {} + {} = {}",
                            kChannels[c], desc.diffuse[c], desc.specular[c], desc.diffuse[c] + desc.specular[c]));
            }
            break;
        }
        case 2:
        case 3: {
            const bool thin = type == 3;
            const JsonObject object(material, thin ? std::initializer_list<std::string_view>{"type", "eta", "fresnel"}
                                                   : std::initializer_list<std::string_view>{"type", "eta", "fresnel",
                                                                                             "absorption"});
            desc.kind = thin ? MaterialKind::ThinDielectric : MaterialKind::Dielectric;
            if (auto v = object.get("eta")) desc.eta = v->numberAbove(0.0f);
            if (auto v = object.get("fresnel")) desc.fresnel = readFresnel(*v);
            if (auto v = object.get("absorption")) desc.absorption = readAbsorption(*v);
            break;
        }
        case 4: {
            const JsonObject object(material, {"type", "tint", "two_sided"});
            desc.kind = MaterialKind::Mirror;
            if (auto v = object.get("tint")) desc.tint = v->rgb(0.0f, 1.0f);
            if (auto v = object.get("two_sided")) desc.twoSided = v->boolean();
            break;
        }
        default: {
            const JsonObject object(material, {"type", "eta", "k", "two_sided"});
            desc.kind = MaterialKind::Conductor;
            const JsonValue etaValue = object.require("eta");
            desc.conductorEta = etaValue.rgb(0.0f);
            for (int c = 0; c < 3; ++c)
                if (!(desc.conductorEta[c] > 0.0f))
                    etaValue.failExpected("a number or an array of 3 numbers (r, g, b), each > 0");
            desc.k = object.require("k").rgb(0.0f);
            if (auto v = object.get("two_sided")) desc.twoSided = v->boolean();
            break;
        }
    }
    return desc;
}

std::vector<MaterialDesc> readMaterials(const JsonValue& value) {
    std::vector<MaterialDesc> materials;
    for (const auto& [name, material] : value.members()) materials.push_back(readMaterial(name, material));
    return materials;
}

uint32_t readMaterialReference(const JsonValue& value, const std::vector<MaterialDesc>& materials) {
    const std::string name = value.string();
    std::string known;
    for (size_t i = 0; i < materials.size(); ++i) {
        if (materials[i].name == name) return uint32_t(i);
        known += (known.empty() ? "" : ", ") + materials[i].name;
    }
    value.fail(fmt::format("unknown material \"{}\" ({})", name,
                           known.empty() ? "the scene defines no materials" : "known materials: " + known));
}

Emission readEmission(const JsonValue& value) {
    const JsonObject object(value, {"radiance", "two_sided"});
    Emission emission;
    emission.radiance = object.require("radiance").rgb(0.0f);
    if (auto v = object.get("two_sided")) emission.twoSided = v->boolean();
    return emission;
}

Transform readTransformStep(const JsonValue& step) {
    const JsonObject object(step, {"translate", "scale", "rotate", "matrix"});
    if (step.json().size() != 1)
        step.failExpected("an object with exactly one key: translate, scale, rotate or matrix");

    if (auto v = object.get("translate")) return Transform::translate(v->vec3());
    if (auto v = object.get("scale")) {
        const bool isVector = v->json().is_array() && v->json().size() == 3;
        if (!v->json().is_number() && !isVector)
            v->failExpected("a non-zero number or an array of 3 non-zero numbers");
        const Vec3f s = isVector ? v->vec3() : Vec3f(v->number(), v->number(), v->number());
        if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f)
            v->failExpected(
                "non-zero scale factors (a zero factor flattens the shape and cannot be inverted)");
        return Transform::scale(s);
    }
    if (auto v = object.get("rotate")) {
        const JsonObject rotate(*v, {"axis", "degrees"});
        const JsonValue axisValue = rotate.require("axis");
        const Vec3f axis = axisValue.vec3();
        if (!(lengthSquared(axis) > 0.0f)) axisValue.failExpected("a non-zero axis");
        return Transform::rotate(rotate.require("degrees").number(), axis);
    }
    const JsonValue v = object.require("matrix");
    if (!v.json().is_array() || v.json().size() != 16) v.failExpected("an array of 16 numbers (4 rows of 4)");
    Matrix4 m;
    for (size_t i = 0; i < 16; ++i) m.m[i / 4][i % 4] = v.element(i).number();
    if (m.m[3] != std::array<float, 4>{0.0f, 0.0f, 0.0f, 1.0f})
        v.fail("expected an affine matrix: the last row must be 0, 0, 0, 1");
    const std::optional<Transform> transform = Transform::fromMatrix(m);
    if (!transform) v.fail("the matrix is singular: it has no inverse");
    return *transform;
}

// The steps apply in order, the first entry first.
Transform readTransform(const JsonValue& value) {
    Transform result;
    for (const JsonValue& step : value.elements()) result = readTransformStep(step) * result;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(result.matrix().m[i][j]) || !std::isfinite(result.inverseMatrix().m[i][j]))
                value.fail("the combined transform overflows a 32-bit float");
    return result;
}

// The uniform scale factor of a transform that is a similarity (rotation, uniform scale,
// translation, mirror), the only kind that maps a sphere to a sphere; empty otherwise.
std::optional<float> similarityScale(const Transform& transform) {
    const auto& m = transform.matrix().m;
    const Vec3f columns[3] = {
        {m[0][0], m[1][0], m[2][0]}, {m[0][1], m[1][1], m[2][1]}, {m[0][2], m[1][2], m[2][2]}};
    const float scale = length(columns[0]);
    const float tolerance = 1e-4f;
    for (int i = 0; i < 3; ++i) {
        if (std::abs(length(columns[i]) - scale) > tolerance * scale) return std::nullopt;
        for (int j = i + 1; j < 3; ++j)
            if (std::abs(dot(columns[i], columns[j])) > tolerance * scale * scale) return std::nullopt;
    }
    return scale;
}

// One motion key: scale, then rotate, then translate (each optional).
TransformKey readTransformKey(const JsonValue& value) {
    const JsonObject object(value, {"scale", "rotate", "translate"});
    TransformKey key;
    if (auto v = object.get("scale")) {
        const bool isVector = v->json().is_array() && v->json().size() == 3;
        if (!v->json().is_number() && !isVector) v->failExpected("a non-zero number or an array of 3 non-zero numbers");
        key.scale = isVector ? v->vec3() : Vec3f(v->number(), v->number(), v->number());
        if (key.scale.x == 0.0f || key.scale.y == 0.0f || key.scale.z == 0.0f) v->failExpected("non-zero scale factors");
    }
    if (auto v = object.get("rotate")) {
        const JsonObject rotate(*v, {"axis", "degrees"});
        const JsonValue axisValue = rotate.require("axis");
        const Vec3f axis = axisValue.vec3();
        if (!(lengthSquared(axis) > 0.0f)) axisValue.failExpected("a non-zero axis");
        key.rotation = Quaternion::fromAxisAngle(axis, rotate.require("degrees").number());
    }
    if (auto v = object.get("translate")) key.translation = v->vec3();
    return key;
}

// Key times, when a scene gives them, must be what penumbra assumes: evenly spaced from the
// shutter opening to its closing.
void checkKeyTimes(const JsonValue& times, size_t keyCount, const CameraDesc& camera) {
    if (times.arraySize() != keyCount)
        times.failExpected(fmt::format("{} times, one per key", keyCount));
    const float open = camera.shutterOpen, close = camera.shutterClose;
    const float tolerance = 1e-4f * std::max(1.0f, std::abs(close - open));
    for (size_t i = 0; i < keyCount; ++i) {
        const JsonValue t = times.element(i);
        const float time = t.number();
        if (time < open - tolerance || time > close + tolerance)
            t.fail(fmt::format("key time {} is outside the shutter [{}, {}] (camera/shutter)", time, open, close));
        const float expected = open + (close - open) * float(i) / float(keyCount - 1);
        if (std::abs(time - expected) > tolerance)
            t.fail(fmt::format("key times must be evenly spaced from shutter open to close; expected {}", expected));
    }
}

struct ShapeMotion {
    MotionTransform transform;
    std::vector<std::vector<Vec3f>> positionKeys;
};

// "motion": {"times": [...], "transforms": [key, ...], "positions": [[p, ...], ...]}; keys are
// evenly spaced over the shutter. Deformation ("positions") is for inline triangle meshes only.
ShapeMotion readMotion(const JsonValue& value, const CameraDesc& camera, bool allowPositions, size_t vertexCount) {
    const JsonObject object(value, {"times", "transforms", "positions"});
    if (camera.shutterClose <= camera.shutterOpen)
        value.fail("motion needs an open shutter: set camera/shutter to [open, close] with close > open");
    ShapeMotion motion;
    size_t keyCount = 0;
    if (auto v = object.get("transforms")) {
        if (v->arraySize() < 2) v->failExpected("an array of at least 2 transform keys");
        for (const JsonValue& key : v->elements()) motion.transform.keys.push_back(readTransformKey(key));
        keyCount = motion.transform.keys.size();
    }
    if (auto v = object.get("positions")) {
        if (!allowPositions) v->fail("per-vertex motion keys are only supported on triangle_mesh shapes");
        if (v->arraySize() < 2) v->failExpected("an array of at least 2 position arrays");
        for (const JsonValue& keyValue : v->elements()) {
            std::vector<Vec3f> key;
            for (const JsonValue& p : keyValue.elements()) key.push_back(p.vec3());
            if (key.size() != vertexCount) keyValue.failExpected(fmt::format("{} positions, as many as the mesh has", vertexCount));
            motion.positionKeys.push_back(std::move(key));
        }
        if (keyCount != 0 && keyCount != motion.positionKeys.size())
            v->failExpected(fmt::format("{} keys, as many as transforms", keyCount));
        keyCount = motion.positionKeys.size();
    }
    if (keyCount == 0) value.failExpected("\"transforms\" or \"positions\" keys");
    if (auto v = object.get("times")) checkKeyTimes(*v, keyCount, camera);
    return motion;
}

TriangleMesh readInlineMesh(const JsonValue& value) {
    TriangleMesh mesh;
    const JsonValue positions = value.requiredMember("positions");
    for (const JsonValue& p : positions.elements()) mesh.positions.push_back(p.vec3());
    if (mesh.positions.empty()) positions.failExpected("a non-empty array of [x, y, z] positions");
    const size_t count = mesh.positions.size();

    const JsonValue indices = value.requiredMember("indices");
    const size_t indexCount = indices.arraySize();
    if (indexCount == 0 || indexCount % 3 != 0)
        indices.failExpected("a non-empty array of vertex indices, 3 per triangle");
    for (const JsonValue& i : indices.elements()) {
        const int64_t index = i.integer(0);
        if (uint64_t(index) >= count)
            i.fail(fmt::format("index {} is out of range: the mesh has {} positions (indices count from 0)",
                               index, count));
        mesh.indices.push_back(uint32_t(index));
    }
    if (auto normals = value.member("normals")) {
        if (normals->arraySize() != count)
            normals->failExpected(fmt::format("an array of {} normals, one per position", count));
        for (const JsonValue& n : normals->elements()) {
            const Vec3f normal = n.vec3();
            if (!(length(normal) > 0.0f)) n.failExpected("a non-zero normal");
            mesh.normals.push_back(normalize(normal));
        }
    }
    if (auto uvs = value.member("uvs")) {
        if (uvs->arraySize() != count)
            uvs->failExpected(fmt::format("an array of {} uvs, one per position", count));
        for (const JsonValue& uv : uvs->elements()) mesh.uvs.push_back(uv.vec2());
    }
    return mesh;
}

// The mesh of a "mesh_file" shape; its file's path is appended to `files`.
TriangleMesh readMeshFile(const JsonValue& value, const fs::path& folder, std::vector<fs::path>& files) {
    const JsonValue fileValue = value.requiredMember("file");
    const fs::path relative = fileValue.string();
    if (relative.empty()) fileValue.failExpected("a file name");
    const fs::path path = relative.is_absolute() ? relative : folder / relative;
    files.push_back(path);
    TriangleMesh mesh;
    try {
        mesh = importMesh(path);
    } catch (const InputError& e) {
        // Name the shape too: the same mesh file may serve several scenes.
        throw InputError(e.where(), fmt::format("{} (mesh file of {}: {})", e.message(), fileValue.file(),
                                                fileValue.pointer()));
    }
    mesh.name = fmt::format("{} ({})", value.pointer(), path.filename().string());
    return mesh;
}

TriangleMesh readQuad(const JsonValue& value) {
    const Vec3f corner = value.requiredMember("corner").vec3();
    const Vec3f edge1 = value.requiredMember("edge1").vec3();
    const Vec3f edge2 = value.requiredMember("edge2").vec3();
    if (!(lengthSquared(cross(edge1, edge2)) > 0.0f))
        value.fail("edge1 and edge2 are zero or parallel, so the quad has no area");
    TriangleMesh mesh;
    // Triangles (0, 1, 2) and (0, 2, 3) both have the front normal cross(edge1, edge2).
    mesh.positions = {corner, corner + edge1, corner + edge1 + edge2, corner + edge2};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

// A disk as a fan of triangles around its centre; front normal = `normal`. With the default 256
// segments its area is 0.99990 of the round disk's, so lighting from it agrees to 1e-4.
TriangleMesh readDisk(const JsonValue& value) {
    const Vec3f center = value.requiredMember("center").vec3();
    const JsonValue normalValue = value.requiredMember("normal");
    const Vec3f normal = normalValue.vec3();
    if (!(lengthSquared(normal) > 0.0f)) normalValue.failExpected("a non-zero normal");
    const float radius = value.requiredMember("radius").numberAbove(0.0f);
    int segments = 256;
    if (auto v = value.member("segments")) segments = int(v->integer(3, 1 << 16));
    const Frame frame = Frame::fromNormal(normalize(normal));
    TriangleMesh mesh;
    mesh.positions.push_back(center);
    mesh.uvs.push_back({0.5f, 0.5f});
    for (int i = 0; i < segments; ++i) {
        const double angle = 2.0 * 3.14159265358979323846 * i / segments;
        const float c = float(std::cos(angle)), sn = float(std::sin(angle));
        mesh.positions.push_back(center + frame.toWorld({radius * c, radius * sn, 0.0f}));
        mesh.uvs.push_back({0.5f + 0.5f * c, 0.5f + 0.5f * sn});
        // Counter-clockwise seen from the front: (centre, i, i + 1) has normal +frame.n.
        mesh.indices.insert(mesh.indices.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % segments)});
    }
    return mesh;
}

void readShape(const JsonValue& value, const fs::path& folder, Scene& scene) {
    const JsonValue typeValue = value.requiredMember("type");
    const size_t type = typeValue.choice({"triangle_mesh", "mesh_file", "quad", "sphere", "disk"});
    const std::vector<MaterialDesc>& materials = scene.materials;

    if (type == 3) {
        const JsonObject object(value, {"type", "center", "radius", "material", "emission", "transform", "motion"});
        Sphere sphere;
        sphere.name = value.pointer();
        sphere.center = object.require("center").vec3();
        sphere.radius = object.require("radius").numberAbove(0.0f);
        sphere.material = readMaterialReference(object.require("material"), materials);
        if (auto v = object.get("emission")) sphere.emission = readEmission(*v);
        if (auto v = object.get("transform")) {
            const Transform transform = readTransform(*v);
            const std::optional<float> scale = similarityScale(transform);
            if (!scale)
                v->fail(
                    "a sphere can only be translated, rotated, mirrored and scaled uniformly; this transform "
                    "would make it an ellipsoid");
            sphere.center = transform.applyPoint(sphere.center);
            sphere.radius *= *scale;
            if (!isFinite(sphere.center) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f))
                v->fail("the transformed sphere does not fit a 32-bit float");
        }
        if (auto v = object.get("motion")) {
            if (sphere.emission.emits()) v->fail("moving light sources are not supported: a sphere with motion cannot emit");
            sphere.motion = readMotion(*v, scene.camera, false, 0).transform;
        }
        scene.spheres.push_back(sphere);
        return;
    }

    TriangleMesh mesh;
    if (type == 0) {
        const JsonObject object(
            value, {"type", "positions", "indices", "normals", "uvs", "material", "emission", "transform", "motion"});
        mesh = readInlineMesh(value);
        mesh.name = value.pointer();
    } else if (type == 1) {
        const JsonObject object(value, {"type", "file", "material", "emission", "transform", "motion"});
        mesh = readMeshFile(value, folder, scene.meshFiles);
    } else if (type == 2) {
        const JsonObject object(value,
                                {"type", "corner", "edge1", "edge2", "material", "emission", "transform", "motion"});
        mesh = readQuad(value);
        mesh.name = value.pointer();
    } else {
        const JsonObject object(
            value, {"type", "center", "normal", "radius", "segments", "material", "emission", "transform", "motion"});
        mesh = readDisk(value);
        mesh.name = value.pointer();
    }
    mesh.material = readMaterialReference(value.requiredMember("material"), materials);
    if (auto v = value.member("emission")) mesh.emission = readEmission(*v);
    if (auto v = value.member("motion")) {
        if (mesh.emission.emits()) v->fail("moving light sources are not supported: a shape with motion cannot emit");
        ShapeMotion motion = readMotion(*v, scene.camera, type == 0, mesh.positions.size());
        mesh.motion = std::move(motion.transform);
        mesh.positionKeys = std::move(motion.positionKeys);
        if (!mesh.positionKeys.empty()) mesh.positions = mesh.positionKeys.front();
    }
    if (auto v = value.member("transform")) {
        const Transform transform = readTransform(*v);
        transformMesh(mesh, transform);
        for (auto& key : mesh.positionKeys)
            for (Vec3f& p : key) p = transform.applyPoint(p);
        for (const auto& key : mesh.positionKeys)
            for (size_t i = 0; i < key.size(); ++i)
                if (!isFinite(key[i]))
                    v->fail(fmt::format("the transform moves vertex {} (counting from 0) beyond the range of a 32-bit float", i));
        for (size_t i = 0; i < mesh.positions.size(); ++i)
            if (!isFinite(mesh.positions[i]))
                v->fail(fmt::format(
                    "the transform moves vertex {} (counting from 0) beyond the range of a 32-bit float", i));
    }
    if (mesh.emission.emits()) {
        double area = 0.0;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Vec3f p0 = mesh.positions[mesh.indices[3 * t]], p1 = mesh.positions[mesh.indices[3 * t + 1]],
                        p2 = mesh.positions[mesh.indices[3 * t + 2]];
            area += 0.5 * length(cross(p1 - p0, p2 - p0));
        }
        if (!(area > 0.0)) value.requiredMember("emission").fail("an emitting shape must have a non-zero area");
    }
    scene.meshes.push_back(std::move(mesh));
}

void readLight(const JsonValue& value, Scene& scene) {
    const size_t type = value.requiredMember("type").choice({"point", "directional"});
    if (type == 0) {
        const JsonObject object(value, {"type", "position", "intensity"});
        PointLight light;
        light.position = object.require("position").vec3();
        light.intensity = object.require("intensity").rgb(0.0f);
        scene.pointLights.push_back(light);
        return;
    }
    const JsonObject object(value, {"type", "direction", "irradiance"});
    const JsonValue directionValue = object.require("direction");
    const Vec3f direction = directionValue.vec3();
    if (!(lengthSquared(direction) > 0.0f)) directionValue.failExpected("a non-zero direction");
    scene.directionalLights.push_back({normalize(direction), object.require("irradiance").rgb(0.0f)});
}

}  // namespace

Scene parseScene(std::string_view jsonText, const fs::path& file) {
    const std::string fileName = file.string();
    const Json document = parseJsonText(jsonText, fileName);
    const JsonValue root(document, fileName, "");
    if (!document.is_object()) root.failExpected("a JSON object holding the scene's sections");
    const JsonObject top(
        root, {"camera", "film", "integrator", "render", "background", "materials", "shapes", "lights"});

    Scene scene;
    scene.sourcePath = file;
    if (auto v = top.get("camera")) scene.camera = readCamera(*v);
    if (auto v = top.get("film")) scene.film = readFilm(*v);
    if (auto v = top.get("integrator")) scene.integrator = readIntegrator(*v);
    if (auto v = top.get("render")) scene.settings = readRender(*v);
    if (auto v = top.get("background")) scene.background = v->rgb(0.0f);
    if (auto v = top.get("materials"))
        scene.materials = readMaterials(*v);  // before the shapes that name them
    if (auto v = top.get("shapes"))
        for (const JsonValue& shape : v->elements()) readShape(shape, file.parent_path(), scene);
    if (auto v = top.get("lights"))
        for (const JsonValue& light : v->elements()) readLight(light, scene);
    return scene;
}

Scene loadScene(const fs::path& file) {
    const std::string name = file.string();
    std::error_code ec;
    if (!fs::exists(file, ec)) throw InputError(SourceLocation{name, 0, 0, ""}, "scene file not found");
    if (fs::is_directory(file, ec))
        throw InputError(SourceLocation{name, 0, 0, ""}, "is a folder, not a scene file");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(SourceLocation{name, 0, 0, ""}, "cannot open the scene file for reading");
    std::ostringstream text;
    text << in.rdbuf();
    return parseScene(text.str(), file);
}

}  // namespace penumbra
