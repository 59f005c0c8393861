#include "geometry/loop_subdivision.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "core/input_limits.h"
#include "geometry/mesh_topology.h"
#include "geometry/vertex_welding.h"

namespace penumbra {

namespace {

using Face = std::array<uint32_t, 3>;
using CornerUvs = std::array<Vec2f, 3>;

// A mesh as the scheme sees it: triangles over welded vertices, uvs per triangle corner.
struct Level {
    std::vector<Vec3f> positions;
    std::vector<Face> faces;
    std::vector<CornerUvs> uvs;  // empty, or one per face
};

// The mesh as a level, its triangles over the vertices `welded` gives (weldedVertexIds).
Level levelOf(const TriangleMesh& mesh, const std::vector<uint32_t>& welded) {
    Level level;
    level.positions = mesh.positions;
    level.faces.reserve(mesh.triangleCount());
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* i = &mesh.indices[3 * t];
        level.faces.push_back({welded[i[0]], welded[i[1]], welded[i[2]]});
        if (!mesh.uvs.empty()) level.uvs.push_back({mesh.uvs[i[0]], mesh.uvs[i[1]], mesh.uvs[i[2]]});
    }
    return level;
}

// The level's topology (geometry/mesh_topology.h).
MeshTopology topologyOfLevel(const Level& level) {
    std::vector<uint32_t> faceStart, corners;
    faceStart.reserve(level.faces.size() + 1);
    corners.reserve(3 * level.faces.size());
    for (const Face& f : level.faces) {
        faceStart.push_back(uint32_t(corners.size()));
        corners.insert(corners.end(), f.begin(), f.end());
    }
    faceStart.push_back(uint32_t(corners.size()));
    return topologyOf(faceStart, corners, level.positions.size(), "Loop", "triangles");
}

// Loop's weight of each neighbour of an interior vertex of valence n (the vertex keeps 1 - n beta):
// 3/16 for n = 3, 3 / (8 n) otherwise (Warren's simplification, which pbrt-v4 also uses).
double loopBeta(size_t n) { return n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * double(n)); }

Vec3f positionSum(const Level& level, const uint32_t* ids, size_t count) {
    Vec3f sum{0.0f, 0.0f, 0.0f};
    for (size_t k = 0; k < count; ++k) sum = sum + level.positions[ids[k]];
    return sum;
}

Level refineOnce(const Level& level) {
    const MeshTopology topology = topologyOfLevel(level);
    const size_t vertexCount = level.positions.size();
    Level next;
    next.positions.resize(vertexCount + topology.edges.size());
    // Even vertices: the old ones, smoothed.
    for (uint32_t v = 0; v < vertexCount; ++v) {
        const Vec3f p = level.positions[v];
        const size_t n = topology.ringSize(v);
        switch (topology.kinds[v]) {
            case VertexKind::Interior: {
                const double beta = loopBeta(n);
                next.positions[v] =
                    p * float(1.0 - double(n) * beta) + positionSum(level, topology.ring(v), n) * float(beta);
                break;
            }
            case VertexKind::Boundary:
                next.positions[v] = p * 0.75f + (level.positions[topology.ring(v)[0]] +
                                                 level.positions[topology.ring(v)[n - 1]]) *
                                                    0.125f;
                break;
            case VertexKind::Unused:
            case VertexKind::Corner:
                next.positions[v] = p;
                break;
        }
    }
    // Odd vertices: one per edge.
    auto opposite = [&](uint32_t face, const MeshTopology::Edge& e) {
        const Face& f = level.faces[face];
        for (uint32_t c : f)
            if (c != e.a && c != e.b) return c;
        return e.a;  // a degenerate triangle repeats a vertex
    };
    for (size_t e = 0; e < topology.edges.size(); ++e) {
        const MeshTopology::Edge& edge = topology.edges[e];
        const Vec3f a = level.positions[edge.a], b = level.positions[edge.b];
        if (edge.faces[1] == MeshTopology::kNoFace) {
            next.positions[vertexCount + e] = (a + b) * 0.5f;
        } else {
            const Vec3f c = level.positions[opposite(edge.faces[0], edge)],
                        d = level.positions[opposite(edge.faces[1], edge)];
            next.positions[vertexCount + e] = (a + b) * 0.375f + (c + d) * 0.125f;
        }
    }
    // Each triangle into four, wound as the old one.
    next.faces.reserve(4 * level.faces.size());
    if (!level.uvs.empty()) next.uvs.reserve(4 * level.faces.size());
    for (size_t f = 0; f < level.faces.size(); ++f) {
        const Face& v = level.faces[f];
        const std::array<uint32_t, 3> m{uint32_t(vertexCount + topology.cornerEdge[3 * f + 0]),
                                        uint32_t(vertexCount + topology.cornerEdge[3 * f + 1]),
                                        uint32_t(vertexCount + topology.cornerEdge[3 * f + 2])};
        next.faces.push_back({v[0], m[0], m[2]});
        next.faces.push_back({v[1], m[1], m[0]});
        next.faces.push_back({v[2], m[2], m[1]});
        next.faces.push_back({m[0], m[1], m[2]});
        if (!level.uvs.empty()) {
            const CornerUvs& t = level.uvs[f];
            const Vec2f m01 = (t[0] + t[1]) * 0.5f, m12 = (t[1] + t[2]) * 0.5f, m20 = (t[2] + t[0]) * 0.5f;
            next.uvs.push_back({t[0], m01, m20});
            next.uvs.push_back({t[1], m12, m01});
            next.uvs.push_back({t[2], m20, m12});
            next.uvs.push_back({m01, m12, m20});
        }
    }
    return next;
}

TriangleMesh meshOf(Level level, const TriangleMesh& like) {
    TriangleMesh mesh;
    mesh.name = like.name;
    mesh.material = like.material;
    mesh.emission = like.emission;
    mesh.motion = like.motion;
    mesh.media = like.media;
    if (level.uvs.empty()) {
        mesh.positions = std::move(level.positions);
        mesh.indices.reserve(3 * level.faces.size());
        for (const Face& f : level.faces) mesh.indices.insert(mesh.indices.end(), f.begin(), f.end());
        return mesh;
    }
    // Face-varying uvs: a vertex per distinct (position, uv).
    CornerVertices ids;
    ids.reserve(level.positions.size());
    mesh.indices.reserve(3 * level.faces.size());
    for (size_t f = 0; f < level.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            bool added;
            const uint32_t vertex = level.faces[f][k];
            mesh.indices.push_back(ids.idOf(vertex, level.uvs[f][k], added));
            if (added) {
                mesh.positions.push_back(level.positions[vertex]);
                mesh.uvs.push_back(level.uvs[f][k]);
            }
        }
    return mesh;
}

// The tangent across the boundary at a boundary vertex with ring r (r[0] and r[n - 1] on the
// boundary): the masks of Hoppe et al., "Piecewise Smooth Surface Reconstruction" (SIGGRAPH 1994),
// as pbrt uses them; the tangent along the boundary is r[n - 1] - r[0].
Vec3f tangentAcrossBoundary(const Level& level, uint32_t v, const uint32_t* r, size_t n) {
    const auto& p = level.positions;
    if (n == 2) return p[r[0]] + p[r[1]] - p[v] * 2.0f;
    if (n == 3) return p[r[1]] - p[v];
    if (n == 4) return p[r[1]] * 2.0f + p[r[2]] * 2.0f - p[r[0]] - p[r[3]] - p[v] * 2.0f;
    const double theta = std::numbers::pi / double(n - 1);
    Vec3f t = (p[r[0]] + p[r[n - 1]]) * float(std::sin(theta));
    for (size_t k = 1; k + 1 < n; ++k)
        t = t + p[r[k]] * float((2.0 * std::cos(theta) - 2.0) * std::sin(double(k) * theta));
    return t;
}

}  // namespace

TriangleMesh refineLoop(const TriangleMesh& control, int levels) {
    if (levels < 0) throw InputError(fmt::format("subdivision levels must be >= 0, found {}", levels));
    const uint64_t triangles = control.triangleCount();
    const uint64_t allowed = std::min(limits::kMaxSubdividedTriangles,
                                      std::max(limits::kMinSubdividedTrianglesAllowed,
                                               triangles * limits::kSubdividedTrianglesPerControlTriangle));
    uint64_t refined = triangles;
    for (int l = 0; l < levels; ++l) {
        refined *= 4;
        if (refined > allowed)
            throw InputError(
                fmt::format("{} levels of subdivision would make more than {} triangles of the {} given, "
                            "penumbra's limit for this mesh (docs/limits.md: 4^5 a triangle, at least 2^22, "
                            "at most 2^26)",
                            levels, allowed, triangles));
    }
    Level level = levelOf(control, weldedVertexIds(control.positions));
    for (int l = 0; l < levels; ++l) level = refineOnce(level);
    return meshOf(std::move(level), control);
}

TriangleMesh moveToLoopLimit(const TriangleMesh& mesh) {
    const std::vector<uint32_t> welded = weldedVertexIds(mesh.positions);
    const Level level = levelOf(mesh, welded);
    const MeshTopology topology = topologyOfLevel(level);
    // The sum of the (area-weighted) normals of the triangles at each vertex: which side is the front.
    std::vector<Vec3f> faceNormals(level.positions.size(), Vec3f{0.0f, 0.0f, 0.0f});
    for (const Face& f : level.faces) {
        const auto& p = level.positions;
        const Vec3f n = cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
        for (uint32_t v : f) faceNormals[v] = faceNormals[v] + n;
    }
    std::vector<Vec3f> limit(level.positions), normal(level.positions.size(), Vec3f{0.0f, 0.0f, 1.0f});
    for (uint32_t v = 0; v < level.positions.size(); ++v) {
        const size_t n = topology.ringSize(v);
        const uint32_t* r = topology.ring(v);
        const Vec3f p = level.positions[v];
        Vec3f tangentNormal{0.0f, 0.0f, 0.0f};
        switch (topology.kinds[v]) {
            case VertexKind::Interior: {
                // The limit mask: the vertex weighs 1 - n gamma, each neighbour gamma.
                const double gamma = 1.0 / (double(n) + 3.0 / (8.0 * loopBeta(n)));
                limit[v] = p * float(1.0 - double(n) * gamma) + positionSum(level, r, n) * float(gamma);
                Vec3f t1{0.0f, 0.0f, 0.0f}, t2{0.0f, 0.0f, 0.0f};
                for (size_t k = 0; k < n; ++k) {
                    const double angle = 2.0 * std::numbers::pi * double(k) / double(n);
                    t1 = t1 + level.positions[r[k]] * float(std::cos(angle));
                    t2 = t2 + level.positions[r[k]] * float(std::sin(angle));
                }
                tangentNormal = cross(t1, t2);
                break;
            }
            case VertexKind::Boundary:
                // The boundary is a uniform cubic B-spline of its vertices, whose limit point is
                // (r[0] + 4 p + r[n - 1]) / 6. pbrt-v4 weighs 3/5 and 1/5, which puts boundary
                // vertices off its own limit curve by 1/30 of the second difference (4 times less
                // per level).
                limit[v] = p * float(2.0 / 3.0) +
                           (level.positions[r[0]] + level.positions[r[n - 1]]) * float(1.0 / 6.0);
                tangentNormal = cross(level.positions[r[n - 1]] - level.positions[r[0]],
                                      tangentAcrossBoundary(level, v, r, n));
                break;
            case VertexKind::Unused:
            case VertexKind::Corner:
                break;
        }
        Vec3f facing = tangentNormal;
        if (!(lengthSquared(facing) > 0.0f) || !std::isfinite(lengthSquared(facing))) facing = faceNormals[v];
        if (dot(facing, faceNormals[v]) < 0.0f) facing = -facing;
        if (lengthSquared(facing) > 0.0f && std::isfinite(lengthSquared(facing)))
            normal[v] = normalize(facing);
    }
    TriangleMesh out = mesh;
    out.normals.resize(out.positions.size());
    for (size_t i = 0; i < out.positions.size(); ++i) {
        out.positions[i] = limit[welded[i]];
        out.normals[i] = normal[welded[i]];
    }
    return out;
}

TriangleMesh loopSubdivide(const TriangleMesh& control, int levels) {
    return moveToLoopLimit(refineLoop(control, levels));
}

}  // namespace penumbra
