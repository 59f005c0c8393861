#include "scenes/shape_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "core/error.h"
#include "core/frame.h"
#include "core/input_limits.h"
#include "core/motion.h"
#include "core/transform.h"
#include "geometry/catmull_clark.h"
#include "geometry/loop_subdivision.h"
#include "scenes/material_reader.h"
#include "scenes/medium_reader.h"
#include "scenes/mesh_import.h"
#include "scenes/texture_reader.h"
#include "scenes/type_table.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// Finite and within the documented coordinate limit in every axis (NaN fails too).
bool withinCoordinateLimit(Vec3f p) {
    return std::abs(p.x) <= limits::kMaxCoordinate && std::abs(p.y) <= limits::kMaxCoordinate &&
           std::abs(p.z) <= limits::kMaxCoordinate;
}

// Emitters and cut-outs are looked up at (u, v) alone (the same value for a hit and a sample).
constexpr const char* kUvOnlyTexture =
    "an emission or an alpha takes a texture of (u, v) only: not one of the point or the normal "
    "(checkerboard_3d, fbm, wrinkled, windy, marble, direction_mix, a spherical, cylindrical or planar "
    "mapping, or a texture of them)";

// "radiance" may be a texture over the shape's (u, v) (scenes/README.md, "Textures"); its average
// over [0, 1)^2 (32 x 32 lookups) then sets the light's power.
Emission readEmission(const JsonValue& value, const fs::path& folder) {
    const JsonObject object(value, {"radiance", "two_sided"});
    Emission emission;
    const JsonValue radiance = object.require("radiance");
    if (isTextureValue(radiance)) {
        emission.texture = std::make_shared<const Texture>(
            readTexture(radiance, folder, 0.0f, std::numeric_limits<float>::max()));
        if (emission.texture->isSpatial()) radiance.fail(kUvOnlyTexture);
        const int n = 32;
        double sum[3] = {0.0, 0.0, 0.0};
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                TextureQuery query;
                query.uv = {(i + 0.5f) / n, (j + 0.5f) / n};
                const Rgb c = emission.texture->evaluate(query);
                for (int k = 0; k < 3; ++k) sum[k] += std::max(0.0f, c[k]);
            }
        emission.radiance = Rgb(float(sum[0] / (n * n)), float(sum[1] / (n * n)), float(sum[2] / (n * n)));
        if (emission.radiance.isBlack())
            radiance.fail(
                "the emission texture is black at every one of 32 x 32 points spread over [0, 1)^2");
    } else {
        emission.radiance = radiance.rgb(0.0f);
    }
    if (auto v = object.get("two_sided")) emission.twoSided = v->boolean();
    return emission;
}

// "alpha": a cut-out (geometry/cut_out.h), a number in [0, 1] or a texture object; null for an
// opaque surface (alpha 1).
std::shared_ptr<const Texture> readAlpha(const JsonValue& value, const fs::path& folder) {
    if (!isTextureValue(value)) {
        const float alpha = value.numberInRange(0.0f, 1.0f);
        if (alpha == 1.0f) return nullptr;
        return std::make_shared<const Texture>(Texture::constant(Rgb(alpha)));
    }
    auto alpha = std::make_shared<const Texture>(readTexture(value, folder, 0.0f, 1.0f));
    if (alpha->isSpatial()) value.fail(kUvOnlyTexture);
    return alpha;
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

}  // namespace

Transform readTransform(const JsonValue& value) {
    Transform result;
    for (const JsonValue& step : value.elements()) result = readTransformStep(step) * result;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(result.matrix().m[i][j]) || !std::isfinite(result.inverseMatrix().m[i][j]))
                value.fail("the combined transform overflows a 32-bit float");
    return result;
}

namespace {

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
        if (!v->json().is_number() && !isVector)
            v->failExpected("a non-zero number or an array of 3 non-zero numbers");
        key.scale = isVector ? v->vec3() : Vec3f(v->number(), v->number(), v->number());
        if (key.scale.x == 0.0f || key.scale.y == 0.0f || key.scale.z == 0.0f)
            v->failExpected("non-zero scale factors");
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
void checkKeyTimes(const JsonValue& times, size_t keyCount, const CameraParams& camera) {
    if (times.arraySize() != keyCount) times.failExpected(fmt::format("{} times, one per key", keyCount));
    const float open = camera.shutterOpen, close = camera.shutterClose;
    const float tolerance = 1e-4f * std::max(1.0f, std::abs(close - open));
    for (size_t i = 0; i < keyCount; ++i) {
        const JsonValue t = times.element(i);
        const float time = t.number();
        if (time < open - tolerance || time > close + tolerance)
            t.fail(fmt::format("key time {} is outside the shutter [{}, {}] (camera/shutter)", time, open,
                               close));
        const float expected = open + (close - open) * float(i) / float(keyCount - 1);
        if (std::abs(time - expected) > tolerance)
            t.fail(fmt::format("key times must be evenly spaced from shutter open to close; expected {}",
                               expected));
    }
}

struct ShapeMotion {
    MotionTransform transform;
    std::vector<std::vector<Vec3f>> positionKeys;
};

// "motion": {"times": [...], "transforms": [key, ...], "positions": [[p, ...], ...]}; keys are
// evenly spaced over the shutter. Deformation ("positions") is for inline triangle meshes only.
ShapeMotion readMotion(const JsonValue& value, const CameraParams& camera, bool allowPositions,
                       size_t vertexCount) {
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
            if (key.size() != vertexCount)
                keyValue.failExpected(fmt::format("{} positions, as many as the mesh has", vertexCount));
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

// Speed trick: inline meshes of a million vertices (a converted pbrt scene's) are read straight
// from the document when every entry is well-formed, without the located access that names each
// value; any entry that is not sends the caller to the checked reading, which reports it
// (bench/README.md, pbrt_parse_bench).
bool readVec3sDirectly(const Json& array, std::vector<Vec3f>& out) {
    if (!array.is_array()) return false;
    out.reserve(array.size());
    for (const Json& entry : array) {
        if (!entry.is_array() || entry.size() != 3) return false;
        float v[3];
        for (size_t i = 0; i < 3; ++i) {
            if (!entry[i].is_number()) return false;
            const double d = entry[i].get<double>();
            if (!(std::abs(d) <= double(limits::kMaxCoordinate))) return false;
            v[i] = float(d);
            if (!(std::abs(v[i]) <= limits::kMaxCoordinate)) return false;
        }
        out.push_back({v[0], v[1], v[2]});
    }
    return true;
}

bool readIndicesDirectly(const Json& array, size_t count, std::vector<uint32_t>& out) {
    if (!array.is_array()) return false;
    out.reserve(array.size());
    for (const Json& entry : array) {
        if (!entry.is_number_integer()) return false;
        const int64_t i = entry.get<int64_t>();
        if (i < 0 || uint64_t(i) >= count) return false;
        out.push_back(uint32_t(i));
    }
    return true;
}

// An inline mesh's "positions": a non-empty array of [x, y, z].
std::vector<Vec3f> readPositions(const JsonValue& shape) {
    const JsonValue positions = shape.requiredMember("positions");
    std::vector<Vec3f> result;
    if (!readVec3sDirectly(positions.json(), result)) {
        result.clear();
        for (const JsonValue& p : positions.elements()) result.push_back(p.vec3());
    }
    if (result.empty()) positions.failExpected("a non-empty array of [x, y, z] positions");
    return result;
}

// "uvs": one [u, v] per vertex of `count`.
std::vector<Vec2f> readVertexUvs(const JsonValue& uvs, size_t count) {
    if (uvs.arraySize() != count)
        uvs.failExpected(fmt::format("an array of {} uvs, one per position", count));
    std::vector<Vec2f> result;
    for (const JsonValue& uv : uvs.elements()) result.push_back(uv.vec2());
    return result;
}

// An inline mesh's polygons: "indices" grouped by "face_sizes" (each 3 or more; default: all
// triangles), and its positions and uvs. Its normals are read by readInlineMesh.
PolygonMesh readInlinePolygons(const JsonValue& value) {
    PolygonMesh mesh;
    mesh.positions = readPositions(value);
    const size_t count = mesh.positions.size();

    const JsonValue indices = value.requiredMember("indices");
    const size_t indexCount = indices.arraySize();
    if (auto sizes = value.member("face_sizes")) {
        uint64_t total = 0;
        for (const JsonValue& size : sizes->elements()) {
            mesh.faceSizes.push_back(uint32_t(size.integer(3, 1 << 16)));
            total += mesh.faceSizes.back();
        }
        if (mesh.faceSizes.empty()) sizes->failExpected("a non-empty array of polygon sizes (3 or more)");
        if (total != indexCount)
            sizes->fail(fmt::format("the polygons have {} corners in all, but \"indices\" has {} entries",
                                    total, indexCount));
    } else {
        if (indexCount == 0 || indexCount % 3 != 0)
            indices.failExpected(
                "a non-empty array of vertex indices, 3 per triangle (or give \"face_sizes\")");
        mesh.faceSizes.assign(indexCount / 3, 3);
    }
    if (!readIndicesDirectly(indices.json(), count, mesh.corners)) {
        mesh.corners.clear();
        for (const JsonValue& i : indices.elements()) {
            const int64_t index = i.integer(0);
            if (uint64_t(index) >= count)
                i.fail(
                    fmt::format("index {} is out of range: the mesh has {} positions (indices count from 0)",
                                index, count));
            mesh.corners.push_back(uint32_t(index));
        }
    }
    if (auto uvs = value.member("uvs")) mesh.uvs = readVertexUvs(*uvs, count);
    return mesh;
}

// "normals": one non-zero normal per vertex of `count`, normalized.
std::vector<Vec3f> readVertexNormals(const JsonValue& normals, size_t count) {
    if (normals.arraySize() != count)
        normals.failExpected(fmt::format("an array of {} normals, one per position", count));
    std::vector<Vec3f> result;
    const bool direct = readVec3sDirectly(normals.json(), result) &&
                        std::all_of(result.begin(), result.end(), [](Vec3f n) { return length(n) > 0.0f; });
    if (direct) {
        for (Vec3f& n : result) n = normalize(n);
        return result;
    }
    result.clear();
    for (const JsonValue& n : normals.elements()) {
        const Vec3f normal = n.vec3();
        if (!(length(normal) > 0.0f)) n.failExpected("a non-zero normal");
        result.push_back(normalize(normal));
    }
    return result;
}

// An inline mesh as triangles (polygons as fans), with its normals.
TriangleMesh readInlineMesh(const JsonValue& value) {
    TriangleMesh mesh = fanTriangulate(readInlinePolygons(value));
    const size_t count = mesh.positions.size();
    if (auto normals = value.member("normals")) mesh.normals = readVertexNormals(*normals, count);
    return mesh;
}

// "subdivision": {"scheme": "loop" (default) | "catmull_clark", "levels": N (default 3)}.
struct Subdivision {
    bool catmullClark = false;
    int levels = 3;
};
std::optional<Subdivision> readSubdivision(const JsonValue& shape) {
    const auto value = shape.member("subdivision");
    if (!value) return std::nullopt;
    const JsonObject object(*value, {"scheme", "levels"});
    Subdivision subdivision;
    if (auto scheme = object.get("scheme"))
        subdivision.catmullClark = scheme->choice({"loop", "catmull_clark"}) == 1;
    if (auto v = object.get("levels"))
        subdivision.levels = int(v->integer(subdivision.catmullClark ? 1 : 0, 16));
    if (auto motion = shape.member("motion"); motion && motion->member("positions"))
        value->fail(
            "a subdivision surface cannot deform (motion \"positions\"): move it with \"transforms\"");
    return subdivision;
}

// `subdivide()` for the shape, its InputError (a non-manifold mesh, too many levels) at the
// shape's "subdivision".
template <typename Subdivide>
TriangleMesh subdividedAt(const JsonValue& shape, Subdivide subdivide) {
    try {
        return subdivide();
    } catch (const InputError& e) {
        shape.requiredMember("subdivision").fail(e.message());
    }
}

// An inline mesh's triangles, of its Loop or Catmull-Clark surface when it asks for one.
TriangleMesh readInlineShapeMesh(const JsonValue& value) {
    const std::optional<Subdivision> subdivision = readSubdivision(value);
    if (subdivision && subdivision->catmullClark) {
        const PolygonMesh polygons = readInlinePolygons(value);
        return subdividedAt(value, [&] { return catmullClarkSubdivide(polygons, subdivision->levels); });
    }
    TriangleMesh mesh = readInlineMesh(value);
    if (!subdivision) return mesh;
    return subdividedAt(value, [&] { return loopSubdivide(mesh, subdivision->levels); });
}

// `import(path)` of a mesh file shape's file, its InputError naming the shape too (the same mesh
// file may serve several scenes).
template <typename Import>
auto importMeshFile(const JsonValue& value, const fs::path& folder, std::vector<fs::path>& files,
                    Import import, fs::path& path) {
    const JsonValue fileValue = value.requiredMember("file");
    const fs::path relative = fileValue.string();
    if (relative.empty()) fileValue.failExpected("a file name");
    path = relative.is_absolute() ? relative : folder / relative;
    files.push_back(path);
    try {
        return import(path);
    } catch (const InputError& e) {
        throw InputError(e.where(), fmt::format("{} (mesh file of {}: {})", e.message(), fileValue.file(),
                                                fileValue.pointer()));
    }
}

// The triangles of a "mesh_file" shape, of its Loop or Catmull-Clark surface when it asks for one
// (a Catmull-Clark surface reads the file's polygons, unsplit); the file's path is appended to `files`.
TriangleMesh readMeshFile(const JsonValue& value, const fs::path& folder, std::vector<fs::path>& files) {
    const std::optional<Subdivision> subdivision = readSubdivision(value);
    fs::path path;
    TriangleMesh mesh;
    if (subdivision && subdivision->catmullClark) {
        PolygonMesh polygons = importMeshFile(
            value, folder, files, [](const fs::path& p) { return importPolygons(p); }, path);
        if (auto front = value.member("front")) {
            // The limit surface's normals replace the file's: only the winding can say which side is the
            // front.
            if (front->choice({"winding", "reversed", "normals", "reversed_normals"}) >= 2)
                front->fail(
                    "a Catmull-Clark surface's front is given by its winding (\"winding\" or \"reversed\")");
            if (front->string() == "reversed") {
                size_t offset = 0;
                for (uint32_t size : polygons.faceSizes) {
                    std::reverse(polygons.corners.begin() + long(offset),
                                 polygons.corners.begin() + long(offset + size));
                    offset += size;
                }
            }
        }
        mesh = subdividedAt(value, [&] { return catmullClarkSubdivide(polygons, subdivision->levels); });
    } else {
        mesh = importMeshFile(
            value, folder, files, [](const fs::path& p) { return importMesh(p); }, path);
        if (auto front = value.member("front"))
            orientFaces(mesh,
                        FrontSide(front->choice({"winding", "reversed", "normals", "reversed_normals"})));
        if (subdivision) mesh = subdividedAt(value, [&] { return loopSubdivide(mesh, subdivision->levels); });
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

// The vector at `key`, which must not be zero (else "expected EXPECTED").
Vec3f requiredNonZeroVector(const JsonValue& value, const char* key, const char* expected) {
    const JsonValue member = value.requiredMember(key);
    const Vec3f v = member.vec3();
    if (!(lengthSquared(v) > 0.0f)) member.failExpected(expected);
    return v;
}

// The angles a disk or cylinder sweeps about its axis `n` (unit): counter-clockwise from
// `start_direction` (default: Frame::fromNormal's first tangent) through `phi_max` degrees (default
// 360), in `segments` steps per full turn (default 256).
struct AngularSweep {
    Frame frame;           // phi = 0 along s, phi = 90 degrees along t = cross(n, s)
    double phiMax = 0.0;   // radians
    int steps = 0;         // segments over [0, phiMax]
    int turnSteps = 0;     // segments a full turn would have
    bool fullTurn = true;  // the last step joins the first

    Vec2f cosSin(int step) const {
        const double angle = phiMax * step / steps;
        return {float(std::cos(angle)), float(std::sin(angle))};
    }
    // The point at `radius` from the axis at a step, in the plane through the axis's origin.
    Vec3f at(float radius, int step) const {
        const Vec2f cs = cosSin(step);
        return frame.toWorld({radius * cs.x, radius * cs.y, 0.0f});
    }
    int rimVertices() const { return fullTurn ? steps : steps + 1; }
};

AngularSweep readSweep(const JsonValue& value, Vec3f n) {
    AngularSweep sweep;
    sweep.frame = Frame::fromNormal(n);
    if (auto v = value.member("start_direction")) {
        const Vec3f start = v->vec3();
        const Vec3f inPlane = start - n * dot(start, n);
        if (!(length(inPlane) > 1e-4f * length(start)))
            v->failExpected("a direction not parallel to the axis");
        sweep.frame.s = normalize(inPlane), sweep.frame.t = cross(n, sweep.frame.s);
    }
    int segments = 256;
    if (auto v = value.member("segments")) segments = int(v->integer(3, 1 << 16));
    double degrees = 360.0;
    if (auto v = value.member("phi_max")) {
        degrees = v->numberInRange(0.0f, 360.0f);
        if (!(degrees > 0.0)) v->failExpected("an angle above 0 degrees");
    }
    sweep.fullTurn = degrees == 360.0;
    sweep.phiMax = sweep.fullTurn ? 2.0 * 3.14159265358979323846 : degrees * (3.14159265358979323846 / 180.0);
    sweep.turnSteps = segments;
    sweep.steps = sweep.fullTurn ? segments : std::max(1, int(std::ceil(segments * degrees / 360.0)));
    return sweep;
}

// A disk as a fan of triangles around its centre (a ring of quads when it has an inner radius);
// front normal = `normal`. With the default 256 segments its area is 0.99990 of the round disk's,
// so lighting from it agrees to 1e-4.
TriangleMesh readDisk(const JsonValue& value) {
    const Vec3f center = value.requiredMember("center").vec3();
    const Vec3f normal = requiredNonZeroVector(value, "normal", "a non-zero normal");
    const float radius = value.requiredMember("radius").numberAbove(0.0f);
    float inner = 0.0f;
    if (auto v = value.member("inner_radius")) {
        inner = v->numberAtLeast(0.0f);
        if (!(inner < radius)) v->failExpected(fmt::format("an inner radius below the radius ({})", radius));
    }
    const AngularSweep sweep = readSweep(value, normalize(normal));
    TriangleMesh mesh;
    // uvs: the plane's, the disk's centre at (0.5, 0.5) and its rim on the unit square's inscribed circle.
    auto addRing = [&](float r) {
        for (int i = 0; i < sweep.rimVertices(); ++i) {
            const Vec2f cs = sweep.cosSin(i);
            mesh.positions.push_back(center + sweep.at(r, i));
            mesh.uvs.push_back({0.5f + 0.5f * (r / radius) * cs.x, 0.5f + 0.5f * (r / radius) * cs.y});
        }
    };
    const int rim = sweep.rimVertices();
    if (inner == 0.0f) {
        mesh.positions.push_back(center);
        mesh.uvs.push_back({0.5f, 0.5f});
        addRing(radius);
        // Counter-clockwise seen from the front: (centre, i, i + 1) has normal +n.
        for (int i = 0; i < sweep.steps; ++i)
            mesh.indices.insert(mesh.indices.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % rim)});
    } else {
        addRing(inner);
        addRing(radius);
        for (int i = 0; i < sweep.steps; ++i) {
            const uint32_t a = uint32_t(i), b = uint32_t((i + 1) % rim), c = uint32_t(rim + (i + 1) % rim),
                           d = uint32_t(rim + i);
            mesh.indices.insert(mesh.indices.end(), {a, d, c, a, c, b});
        }
    }
    return mesh;
}

// An open cylinder (pbrt-v4's `cylinder`: no caps) of `radius` around the segment from `base` to
// `base + axis`, as a band of `segments` quads with the cylinder's own normals at its vertices;
// `front` "outside" (default) or "inside". With the default 256 segments its area is 0.99997 of
// the round cylinder's.
TriangleMesh readCylinder(const JsonValue& value) {
    const Vec3f base = value.requiredMember("base").vec3();
    const Vec3f axis = requiredNonZeroVector(value, "axis", "a non-zero axis (from the base to the top)");
    const float radius = value.requiredMember("radius").numberAbove(0.0f);
    bool inside = false;
    if (auto v = value.member("front")) inside = v->choice({"outside", "inside"}) == 1;
    const AngularSweep sweep = readSweep(value, normalize(axis));
    TriangleMesh mesh;
    // steps + 1 vertices a ring: a full turn ends on a copy of its first vertex with u = 1, so that
    // textures do not wrap back across the last quad.
    const int rim = sweep.steps + 1;
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i < rim; ++i) {
            const Vec3f radial = sweep.at(1.0f, sweep.fullTurn && i == sweep.steps ? 0 : i);
            mesh.positions.push_back(base + axis * float(ring) + radial * radius);
            mesh.normals.push_back(inside ? -radial : radial);
            // pbrt-v4's (u, v): the angle's fraction of phi_max, and the height's.
            mesh.uvs.push_back({float(i) / float(sweep.steps), float(ring)});
        }
    for (int i = 0; i < sweep.steps; ++i) {
        const uint32_t a = uint32_t(i), b = uint32_t(i + 1), c = uint32_t(rim + i + 1), d = uint32_t(rim + i);
        // (a, b, c) turns counter-clockwise about the axis, then up: its normal points outward.
        if (inside)
            mesh.indices.insert(mesh.indices.end(), {a, c, b, a, d, c});
        else
            mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
    return mesh;
}

// What every shape reader is given: the scene so far (its materials, its camera's shutter, the
// mesh files named) and the scene file's folder.
struct ShapeContext {
    Scene& scene;
    const fs::path& folder;
    const std::vector<std::string>& prototypeNames;  // prototypeNames[i] names scene.prototypes[i]
};

void addMeshShape(TriangleMesh mesh, const JsonValue& value, bool allowPositionKeys, Scene& scene,
                  const fs::path& folder);

// A sphere as triangles: for part of one (pbrt-v4's zmin, zmax, phimax) or an ellipsoid (a sphere
// under a non-uniform transform), which the analytic sphere of both backends is not. Rings of
// `segments` / 2 steps over a half turn of the polar angle and the azimuth's sweep of `segments` a
// turn, between the heights z_min and z_max above the centre; the vertices on the sphere, with its
// normals; uvs as the analytic sphere's (u the azimuth over a turn, v the polar angle over a half).
TriangleMesh readSphereMesh(const JsonValue& value) {
    const Vec3f center = value.requiredMember("center").vec3();
    const float radius = value.requiredMember("radius").numberAbove(0.0f);
    float zMin = -radius, zMax = radius;
    if (auto v = value.member("z_min")) zMin = v->numberInRange(-radius, radius);
    if (auto v = value.member("z_max")) zMax = v->numberInRange(-radius, radius);
    if (!(zMin < zMax)) value.fail(fmt::format("z_min ({}) must be below z_max ({})", zMin, zMax));
    const AngularSweep sweep = readSweep(value, {0.0f, 0.0f, 1.0f});
    const double pi = 3.14159265358979323846;
    const double thetaTop = std::acos(std::clamp(double(zMax) / radius, -1.0, 1.0));
    const double thetaBottom = std::acos(std::clamp(double(zMin) / radius, -1.0, 1.0));
    const bool topPole = thetaTop == 0.0, bottomPole = thetaBottom == pi;
    // Two rings at least between two poles, whose own quads are triangles.
    const int rings = std::max(topPole && bottomPole ? 2 : 1,
                               int(std::ceil((thetaBottom - thetaTop) / pi * (sweep.turnSteps / 2))));
    const int columns = sweep.steps + 1;  // a full turn ends on a copy of its first column, with u = 1
    TriangleMesh mesh;
    for (int i = 0; i <= rings; ++i) {
        const double theta = thetaTop + (thetaBottom - thetaTop) * i / rings;
        const float sinTheta = float(std::sin(theta)), cosTheta = float(std::cos(theta));
        for (int j = 0; j < columns; ++j) {
            const Vec3f around = sweep.at(sinTheta, sweep.fullTurn && j == sweep.steps ? 0 : j);
            const Vec3f n{around.x, around.y, cosTheta};
            mesh.positions.push_back(center + n * radius);
            mesh.normals.push_back(normalize(n));
            mesh.uvs.push_back(
                {float(sweep.phiMax / (2.0 * pi)) * float(j) / float(sweep.steps), float(theta / pi)});
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < sweep.steps; ++j) {
            const uint32_t a = uint32_t(i * columns + j), b = a + 1, d = a + uint32_t(columns), c = d + 1;
            // Down the polar angle, then round the azimuth: the normal points outward. A pole's
            // quads are triangles.
            if (!(bottomPole && i == rings - 1)) mesh.indices.insert(mesh.indices.end(), {a, d, c});
            if (!(topPole && i == 0)) mesh.indices.insert(mesh.indices.end(), {a, c, b});
        }
    return mesh;
}

void readSphere(const JsonValue& value, ShapeContext& context) {
    Scene& scene = context.scene;
    // Partial spheres and cut-outs need triangles; so do ellipsoids, below.
    const bool partial =
        value.member("z_min") || value.member("z_max") || value.member("phi_max") || value.member("alpha");
    const auto transformValue = value.member("transform");
    const Transform transform = transformValue ? readTransform(*transformValue) : Transform{};
    const std::optional<float> scale = similarityScale(transform);  // none: an ellipsoid
    if (partial || !scale) {
        TriangleMesh mesh = readSphereMesh(value);
        mesh.name = value.pointer();
        addMeshShape(std::move(mesh), value, false, scene, context.folder);
        return;
    }
    for (const char* key : {"start_direction", "segments"})
        if (auto v = value.member(key))
            v->fail(fmt::format("\"{}\" is for partial spheres and ellipsoids", key));
    Sphere sphere;
    sphere.name = value.pointer();
    sphere.center = value.requiredMember("center").vec3();
    sphere.radius = value.requiredMember("radius").numberAbove(0.0f);
    sphere.material = readMaterialReference(value.requiredMember("material"), scene.materialNames);
    sphere.media = readMediumInterface(value, scene.mediumNames);
    if (auto v = value.member("emission")) sphere.emission = readEmission(*v, context.folder);
    if (transformValue) {
        sphere.center = transform.applyPoint(sphere.center);
        sphere.radius *= *scale;
        if (!isFinite(sphere.center) || !std::isfinite(sphere.radius) || !(sphere.radius > 0.0f))
            transformValue->fail("the transformed sphere does not fit a 32-bit float");
    }
    if (!withinCoordinateLimit(sphere.center) || !(sphere.radius <= limits::kMaxCoordinate))
        value.fail(fmt::format(
            "the sphere (centre ({}, {}, {}), radius {}) reaches beyond the coordinate limit of {:g} "
            "(docs/limits.md)",
            sphere.center.x, sphere.center.y, sphere.center.z, sphere.radius, limits::kMaxCoordinate));
    if (auto v = value.member("motion")) {
        if (sphere.emission.emits())
            v->fail("moving light sources are not supported: a sphere with motion cannot emit");
        sphere.motion = readMotion(*v, scene.camera, false, 0).transform;
    }
    scene.spheres.push_back(sphere);
}

// `transform` (a JSON value) moved `vertices` beyond the range of a float: an error at it.
void checkTransformedVertices(const JsonValue& transform, const std::vector<Vec3f>& vertices) {
    for (size_t i = 0; i < vertices.size(); ++i)
        if (!isFinite(vertices[i]))
            transform.fail(fmt::format(
                "the transform moves vertex {} (counting from 0) beyond the range of a 32-bit float", i));
}

// Derived geometry too (corner + edge, a transform, a mesh file's vertices): a vertex at
// infinity or near 3e38 would make its triangles vanish silently.
void checkVerticesWithinLimit(const JsonValue& shape, const std::vector<Vec3f>& vertices) {
    for (size_t i = 0; i < vertices.size(); ++i)
        if (!withinCoordinateLimit(vertices[i]))
            shape.fail(fmt::format(
                "vertex {} (counting from 0) lies at ({}, {}, {}), beyond the coordinate limit of "
                "{:g} (docs/limits.md)",
                i, vertices[i].x, vertices[i].y, vertices[i].z, limits::kMaxCoordinate));
}

// What all triangle-mesh shapes share, once their own reader has made the mesh: the material,
// emission, motion and transform keys.
void addMeshShape(TriangleMesh mesh, const JsonValue& value, bool allowPositionKeys, Scene& scene,
                  const fs::path& folder) {
    mesh.material = readMaterialReference(value.requiredMember("material"), scene.materialNames);
    mesh.media = readMediumInterface(value, scene.mediumNames);
    if (auto v = value.member("emission")) mesh.emission = readEmission(*v, folder);
    if (auto v = value.member("alpha")) mesh.alpha = readAlpha(*v, folder);
    if (auto v = value.member("motion")) {
        if (mesh.emission.emits())
            v->fail("moving light sources are not supported: a shape with motion cannot emit");
        ShapeMotion motion = readMotion(*v, scene.camera, allowPositionKeys, mesh.positions.size());
        mesh.motion = std::move(motion.transform);
        mesh.positionKeys = std::move(motion.positionKeys);
        if (!mesh.positionKeys.empty()) mesh.positions = mesh.positionKeys.front();
    }
    if (auto v = value.member("transform")) {
        const Transform transform = readTransform(*v);
        transformMesh(mesh, transform);
        for (auto& key : mesh.positionKeys)
            for (Vec3f& p : key) p = transform.applyPoint(p);
        for (const auto& key : mesh.positionKeys) checkTransformedVertices(*v, key);
        checkTransformedVertices(*v, mesh.positions);
    }
    checkVerticesWithinLimit(value, mesh.positions);
    for (const auto& key : mesh.positionKeys)
        for (size_t i = 0; i < key.size(); ++i)
            if (!withinCoordinateLimit(key[i]))
                value.fail(fmt::format(
                    "vertex {} (counting from 0) of a motion key lies beyond the coordinate limit "
                    "of {:g} (docs/limits.md)",
                    i, limits::kMaxCoordinate));
    if (mesh.emission.emits()) {
        double area = 0.0;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Vec3f p0 = mesh.positions[mesh.indices[3 * t]],
                        p1 = mesh.positions[mesh.indices[3 * t + 1]],
                        p2 = mesh.positions[mesh.indices[3 * t + 2]];
            area += 0.5 * length(cross(p1 - p0, p2 - p0));
        }
        if (!(area > 0.0))
            value.requiredMember("emission").fail("an emitting shape must have a non-zero area");
    }
    scene.meshes.push_back(std::move(mesh));
}

void readTriangleMeshShape(const JsonValue& value, ShapeContext& context) {
    TriangleMesh mesh = readInlineShapeMesh(value);
    mesh.name = value.pointer();
    addMeshShape(std::move(mesh), value, true, context.scene, context.folder);
}

void readMeshFileShape(const JsonValue& value, ShapeContext& context) {
    addMeshShape(readMeshFile(value, context.folder, context.scene.meshFiles), value, false, context.scene,
                 context.folder);
}

void readQuadShape(const JsonValue& value, ShapeContext& context) {
    TriangleMesh mesh = readQuad(value);
    mesh.name = value.pointer();
    addMeshShape(std::move(mesh), value, false, context.scene, context.folder);
}

void readDiskShape(const JsonValue& value, ShapeContext& context) {
    TriangleMesh mesh = readDisk(value);
    mesh.name = value.pointer();
    addMeshShape(std::move(mesh), value, false, context.scene, context.folder);
}

void readCylinderShape(const JsonValue& value, ShapeContext& context) {
    TriangleMesh mesh = readCylinder(value);
    mesh.name = value.pointer();
    addMeshShape(std::move(mesh), value, false, context.scene, context.folder);
}

// Whether every vertex of `mesh` placed by `toWorld` lies within the coordinate limit: the
// corners of its box, placed, bound them all.
bool placedWithinCoordinateLimit(const TriangleMesh& mesh, const Transform& toWorld) {
    if (mesh.positions.empty()) return true;
    Vec3f lower = mesh.positions.front(), upper = lower;
    for (const Vec3f& p : mesh.positions) {
        lower = min(lower, p);
        upper = max(upper, p);
    }
    for (int c = 0; c < 8; ++c)
        if (!withinCoordinateLimit(toWorld.applyPoint(
                {(c & 1) ? upper.x : lower.x, (c & 2) ? upper.y : lower.y, (c & 4) ? upper.z : lower.z})))
            return false;
    return true;
}

// {"type": "instance", "prototype": name, "material": name, "transform" or "motion"}: a placement
// of a mesh of the scene's "prototypes".
void readInstance(const JsonValue& value, ShapeContext& context) {
    Scene& scene = context.scene;
    MeshInstance instance;
    instance.name = value.pointer();
    const JsonValue prototypeValue = value.requiredMember("prototype");
    const std::string name = prototypeValue.string();
    const auto found = std::find(context.prototypeNames.begin(), context.prototypeNames.end(), name);
    if (found == context.prototypeNames.end()) {
        std::string known;
        for (const std::string& n : context.prototypeNames) known += (known.empty() ? "" : ", ") + n;
        prototypeValue.fail(
            fmt::format("unknown prototype \"{}\" ({})", name,
                        known.empty() ? "the scene defines no prototypes" : "known prototypes: " + known));
    }
    instance.prototype = uint32_t(found - context.prototypeNames.begin());
    instance.material = readMaterialReference(value.requiredMember("material"), scene.materialNames);
    instance.media = readMediumInterface(value, scene.mediumNames);
    if (auto v = value.member("emission"))
        v->fail(
            "an instance cannot emit light: give the emitting mesh as a shape of its own (triangle_mesh, "
            "mesh_file, quad or disk)");
    const auto transformValue = value.member("transform");
    if (transformValue) instance.placement = readTransform(*transformValue);
    if (auto v = value.member("motion")) {
        if (transformValue)
            v->fail(
                "an instance takes either transform or motion, not both: motion keys scale, rotate and "
                "translate the prototype themselves");
        instance.motion = readMotion(*v, scene.camera, false, 0).transform;
    }
    const TriangleMesh& prototype = scene.prototypes[instance.prototype];
    const std::vector<TransformKey> keys = instance.motion.keys;
    bool within = keys.empty() ? placedWithinCoordinateLimit(prototype, instance.placement) : true;
    for (const TransformKey& key : keys)
        within = within && placedWithinCoordinateLimit(prototype, key.toTransform());
    if (!within)
        value.fail(
            fmt::format("the placed prototype \"{}\" reaches beyond the coordinate limit of {:g} "
                        "(docs/limits.md)",
                        name, limits::kMaxCoordinate));
    scene.instances.push_back(std::move(instance));
}

// {"type": "curves", "points": [[x, y, z], ...], "curve_sizes": [n, ...] (default: one curve of all
// points), "basis": "bezier" | "bspline", "curve_type": "flat" | "cylinder" | "ribbon", "width": w
// or [w0, w1] (linear along each curve) or "curve_widths": [[w0, w1], ...] (one pair a curve),
// "normals" (ribbons: one per segment boundary of every curve, in order), "split_depth",
// "material", "transform", "inside"/"outside"}: geometry/curves.h.
void readCurves(const JsonValue& value, ShapeContext& context) {
    Scene& scene = context.scene;
    Curves curves;
    curves.name = value.pointer();
    if (auto v = value.member("curve_type"))
        curves.type = std::array{CurveType::Flat, CurveType::Cylinder,
                                 CurveType::Ribbon}[v->choice({"flat", "cylinder", "ribbon"})];
    CurveBasis basis = CurveBasis::Bezier;
    if (auto v = value.member("basis"))
        basis = v->choice({"bezier", "bspline"}) == 1 ? CurveBasis::BSpline : basis;
    const JsonValue pointsValue = value.requiredMember("points");
    std::vector<Vec3f> points;
    if (!readVec3sDirectly(pointsValue.json(), points)) {
        points.clear();
        for (const JsonValue& p : pointsValue.elements()) points.push_back(p.vec3());
    }
    std::vector<size_t> sizes;
    if (auto v = value.member("curve_sizes")) {
        size_t total = 0;
        for (const JsonValue& size : v->elements()) {
            sizes.push_back(size_t(size.integer(4, int64_t(points.size()))));
            total += sizes.back();
        }
        if (total != points.size())
            v->fail(fmt::format("the curve sizes add up to {} points, and \"points\" holds {}", total,
                                points.size()));
    } else {
        sizes.push_back(points.size());
    }
    // Each curve's start and end widths: "width" for all, or "curve_widths" one pair a curve.
    std::vector<std::pair<float, float>> widths;
    const auto widthValue = value.member("width"), curveWidths = value.member("curve_widths");
    if (bool(widthValue) == bool(curveWidths))
        value.fail(
            "curves take either \"width\" (all curves) or \"curve_widths\" (one [start, end] a curve)");
    auto readPair = [](const JsonValue& pair) -> std::pair<float, float> {
        if (!pair.json().is_array() || pair.arraySize() != 2) pair.failExpected("[start width, end width]");
        return {pair.element(0).numberInRange(0.0f, limits::kMaxCoordinate),
                pair.element(1).numberInRange(0.0f, limits::kMaxCoordinate)};
    };
    if (curveWidths) {
        for (const JsonValue& pair : curveWidths->elements()) widths.push_back(readPair(pair));
        if (widths.size() != sizes.size())
            curveWidths->fail(fmt::format("{} curves take {} width pairs, not {}", sizes.size(), sizes.size(),
                                          widths.size()));
    } else if (widthValue->json().is_array()) {
        widths.assign(sizes.size(), readPair(*widthValue));
    } else {
        const float width = widthValue->numberInRange(0.0f, limits::kMaxCoordinate);
        widths.assign(sizes.size(), {width, width});
    }
    std::vector<Vec3f> normals;
    if (auto v = value.member("normals")) {
        if (curves.type != CurveType::Ribbon)
            v->fail("\"normals\" orient ribbons: set \"curve_type\": \"ribbon\"");
        for (const JsonValue& n : v->elements()) {
            const Vec3f normal = n.vec3();
            const float normalLength = length(normal);
            if (!(normalLength > 0.0f) || !std::isfinite(normalLength))
                n.fail("a ribbon's normal must be non-zero, its length within a 32-bit float");
            normals.push_back(normalize(normal));
        }
    }
    int splitDepth = 0;
    if (auto v = value.member("split_depth")) splitDepth = int(v->integer(0, 5));
    std::optional<Transform> transform;
    if (auto v = value.member("transform")) {
        transform = readTransform(*v);
        const std::optional<float> scale = similarityScale(*transform);
        if (!scale) v->fail("curves take a similarity transform only (their widths would stretch unevenly)");
        for (Vec3f& p : points) p = transform->applyPoint(p);
        checkTransformedVertices(*v, points);
        for (Vec3f& n : normals) n = normalize(transform->applyNormal(n));
        for (auto& [w0, w1] : widths) w0 *= *scale, w1 *= *scale;
    }
    checkVerticesWithinLimit(value, points);
    size_t first = 0, firstNormal = 0;
    for (size_t c = 0; c < sizes.size(); ++c) {
        const size_t segments = curveSegmentCount(sizes[c], basis);
        if (segments == 0)
            value.fail(fmt::format("curve {} (counting from 0) has {} points: a {} curve needs {}", c,
                                   sizes[c], basis == CurveBasis::Bezier ? "Bezier" : "B-spline",
                                   basis == CurveBasis::Bezier ? "3 n + 1 (4, 7, 10, ...)" : "at least 4"));
        std::span<const Vec3f> curveNormals;
        if (curves.type == CurveType::Ribbon) {
            if (normals.size() < firstNormal + segments + 1)
                value.fail(
                    fmt::format("a ribbon needs a normal at each segment boundary: curve {} (counting from "
                                "0) needs {} more than \"normals\" holds",
                                c, firstNormal + segments + 1 - normals.size()));
            curveNormals = std::span<const Vec3f>(normals).subspan(firstNormal, segments + 1);
            firstNormal += segments + 1;
        }
        const std::span<const Vec3f> curvePoints = std::span<const Vec3f>(points).subspan(first, sizes[c]);
        appendCurve(curves, curvePoints, linearCurveRadii(sizes[c], basis, widths[c].first, widths[c].second),
                    basis, curveNormals, splitDepth);
        first += sizes[c];
    }
    if (curves.type == CurveType::Ribbon && firstNormal != normals.size())
        value.requiredMember("normals").fail(fmt::format(
            "the ribbons take {} normals (one a segment boundary), not {}", firstNormal, normals.size()));
    curves.material = readMaterialReference(value.requiredMember("material"), scene.materialNames);
    curves.media = readMediumInterface(value, scene.mediumNames);
    scene.curves.push_back(std::move(curves));
}

// {"type": "bilinear_mesh", "positions": [[x, y, z], ...], "indices": [p00, p10, p01, p11, ...]
// (four a patch), "normals", "uvs" (one a position), "reverse_orientation", "material",
// "transform" (any affine map: it maps a bilinear patch to a bilinear patch), "inside"/"outside"}:
// geometry/bilinear_patches.h.
void readBilinearMesh(const JsonValue& value, ShapeContext& context) {
    Scene& scene = context.scene;
    BilinearPatches patches;
    patches.name = value.pointer();
    patches.positions = readPositions(value);
    const size_t count = patches.positions.size();
    const JsonValue indices = value.requiredMember("indices");
    if (indices.arraySize() == 0 || indices.arraySize() % 4 != 0)
        indices.failExpected("a non-empty array of vertex indices, 4 per patch (p00, p10, p01, p11)");
    if (!readIndicesDirectly(indices.json(), count, patches.indices)) {
        patches.indices.clear();
        for (const JsonValue& i : indices.elements())
            patches.indices.push_back(uint32_t(i.integer(0, int64_t(count) - 1)));
    }
    if (auto v = value.member("normals")) patches.normals = readVertexNormals(*v, count);
    if (auto uvs = value.member("uvs")) patches.uvs = readVertexUvs(*uvs, count);
    if (auto v = value.member("reverse_orientation")) patches.reversed = v->boolean();
    if (auto v = value.member("transform")) {
        const Transform transform = readTransform(*v);
        for (Vec3f& p : patches.positions) p = transform.applyPoint(p);
        checkTransformedVertices(*v, patches.positions);
        for (Vec3f& n : patches.normals) n = normalize(transform.applyNormal(n));
        // A mirroring transform turns cross(dp/du, dp/dv) over: the front stays where it was.
        if (transform.swapsHandedness()) patches.reversed = !patches.reversed;
    }
    checkVerticesWithinLimit(value, patches.positions);
    patches.material = readMaterialReference(value.requiredMember("material"), scene.materialNames);
    patches.media = readMediumInterface(value, scene.mediumNames);
    scene.patches.push_back(std::move(patches));
}

using ShapeReader = void (*)(const JsonValue&, ShapeContext&);

const std::array<TypeRow<ShapeReader>, 9> kShapeTypes{{
    {"triangle_mesh",
     {"type", "positions", "indices", "face_sizes", "normals", "uvs", "subdivision", "material", "alpha",
      "emission", "transform", "motion", "inside", "outside"},
     readTriangleMeshShape},
    {"mesh_file",
     {"type", "file", "front", "subdivision", "material", "alpha", "emission", "transform", "motion",
      "inside", "outside"},
     readMeshFileShape},
    {"quad",
     {"type", "corner", "edge1", "edge2", "material", "alpha", "emission", "transform", "motion", "inside",
      "outside"},
     readQuadShape},
    {"sphere",
     {"type", "center", "radius", "z_min", "z_max", "phi_max", "start_direction", "segments", "material",
      "alpha", "emission", "transform", "motion", "inside", "outside"},
     readSphere},
    {"disk",
     {"type", "center", "normal", "radius", "inner_radius", "phi_max", "start_direction", "segments",
      "material", "alpha", "emission", "transform", "motion", "inside", "outside"},
     readDiskShape},
    {"cylinder",
     {"type", "base", "axis", "radius", "phi_max", "start_direction", "front", "segments", "material",
      "alpha", "emission", "transform", "motion", "inside", "outside"},
     readCylinderShape},
    {"instance",
     {"type", "prototype", "material", "emission", "transform", "motion", "inside", "outside"},
     readInstance},
    {"curves",
     {"type", "points", "curve_sizes", "basis", "curve_type", "width", "curve_widths", "normals",
      "split_depth", "material", "transform", "inside", "outside"},
     readCurves},
    {"bilinear_mesh",
     {"type", "positions", "indices", "normals", "uvs", "reverse_orientation", "material", "transform",
      "inside", "outside"},
     readBilinearMesh},
}};

// A prototype: a mesh in its own space, stored once and placed by "instance" shapes. Its geometry
// is given as for the mesh shapes (with an optional transform baked in); material, emission and
// motion belong to the instances.
using PrototypeReader = TriangleMesh (*)(const JsonValue&, ShapeContext&);

TriangleMesh readInlinePrototype(const JsonValue& value, ShapeContext&) { return readInlineShapeMesh(value); }
TriangleMesh readMeshFilePrototype(const JsonValue& value, ShapeContext& context) {
    return readMeshFile(value, context.folder, context.scene.meshFiles);
}
TriangleMesh readQuadPrototype(const JsonValue& value, ShapeContext&) { return readQuad(value); }
TriangleMesh readDiskPrototype(const JsonValue& value, ShapeContext&) { return readDisk(value); }
TriangleMesh readCylinderPrototype(const JsonValue& value, ShapeContext&) { return readCylinder(value); }

const std::array<TypeRow<PrototypeReader>, 5> kPrototypeTypes{{
    {"triangle_mesh",
     {"type", "positions", "indices", "face_sizes", "normals", "uvs", "subdivision", "alpha", "transform"},
     readInlinePrototype},
    {"mesh_file", {"type", "file", "front", "subdivision", "alpha", "transform"}, readMeshFilePrototype},
    {"quad", {"type", "corner", "edge1", "edge2", "alpha", "transform"}, readQuadPrototype},
    {"disk",
     {"type", "center", "normal", "radius", "inner_radius", "phi_max", "start_direction", "segments", "alpha",
      "transform"},
     readDiskPrototype},
    {"cylinder",
     {"type", "base", "axis", "radius", "phi_max", "start_direction", "front", "segments", "alpha",
      "transform"},
     readCylinderPrototype},
}};

}  // namespace

void readPrototypes(const JsonValue& section, const fs::path& folder, Scene& scene,
                    std::vector<std::string>& names) {
    ShapeContext context{scene, folder, names};
    for (const auto& [name, value] : section.members()) {
        TriangleMesh mesh = findTypeRow<PrototypeReader>(value, kPrototypeTypes).read(value, context);
        if (mesh.name.empty()) mesh.name = value.pointer();
        if (auto v = value.member("alpha")) mesh.alpha = readAlpha(*v, folder);
        if (auto v = value.member("transform")) {
            transformMesh(mesh, readTransform(*v));
            checkTransformedVertices(*v, mesh.positions);
        }
        checkVerticesWithinLimit(value, mesh.positions);
        context.scene.prototypes.push_back(std::move(mesh));
        names.push_back(name);
    }
}

void readShapes(const JsonValue& section, const fs::path& folder,
                const std::vector<std::string>& prototypeNames, Scene& scene) {
    ShapeContext context{scene, folder, prototypeNames};
    for (const JsonValue& shape : section.elements())
        findTypeRow<ShapeReader>(shape, kShapeTypes).read(shape, context);
    for (Sphere& sphere : scene.spheres)
        sphere.needsUv = scene.materials[sphere.material].isTextured() ||
                         scene.materials[sphere.material].mix() || sphere.emission.texture != nullptr;
}

}  // namespace penumbra
