#include "geometry/catmull_clark.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>

#include "core/error.h"
#include "core/input_limits.h"
#include "geometry/mesh_topology.h"
#include "geometry/vertex_welding.h"

namespace penumbra {

namespace {

// A mesh as the scheme sees it: polygons over welded vertices, uvs per corner.
struct Level {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> faceStart{0};  // face f: corners[faceStart[f], faceStart[f + 1])
    std::vector<uint32_t> corners;
    std::vector<Vec2f> cornerUvs;  // empty, or one per corner
    size_t faceCount() const { return faceStart.size() - 1; }
    uint32_t sizeOf(size_t f) const { return faceStart[f + 1] - faceStart[f]; }
    // Corner k (taken modulo the face's size) of face f, as an index into `corners`.
    uint32_t corner(size_t f, uint32_t k) const { return faceStart[f] + k % sizeOf(f); }
};

// The level's topology, with a vertex of a single face made a corner (it stays where it is).
MeshTopology topologyOfLevel(const Level& level) {
    MeshTopology topology =
        topologyOf(level.faceStart, level.corners, level.positions.size(), "Catmull-Clark", "faces");
    for (uint32_t v = 0; v < level.positions.size(); ++v)
        if (topology.kinds[v] == VertexKind::Boundary && topology.ringSize(v) == 2)
            topology.kinds[v] = VertexKind::Corner;
    return topology;
}

Level refineOnce(const Level& level) {
    const MeshTopology topology = topologyOfLevel(level);
    const size_t vertexCount = level.positions.size(), edgeCount = topology.edges.size();
    const size_t faceCount = level.faceCount();
    Level next;
    next.positions.resize(vertexCount + edgeCount + faceCount);
    const size_t edgeBase = vertexCount, faceBase = vertexCount + edgeCount;
    // Face points: centroids.
    for (size_t f = 0; f < faceCount; ++f) {
        Vec3f sum{0.0f, 0.0f, 0.0f};
        for (uint32_t c = level.faceStart[f]; c < level.faceStart[f + 1]; ++c)
            sum = sum + level.positions[level.corners[c]];
        next.positions[faceBase + f] = sum / float(level.sizeOf(f));
    }
    // Edge points.
    for (size_t e = 0; e < edgeCount; ++e) {
        const MeshTopology::Edge& edge = topology.edges[e];
        const Vec3f ends = level.positions[edge.a] + level.positions[edge.b];
        next.positions[edgeBase + e] = edge.faces[1] == MeshTopology::kNoFace
                                           ? ends * 0.5f
                                           : (ends + next.positions[faceBase + edge.faces[0]] +
                                              next.positions[faceBase + edge.faces[1]]) *
                                                 0.25f;
    }
    // Vertex points.
    for (uint32_t v = 0; v < vertexCount; ++v) {
        const Vec3f s = level.positions[v];
        const size_t n = topology.ringSize(v);
        const uint32_t* neighbour = topology.ring(v);
        const uint32_t* face = topology.ringFacesOf(v);
        switch (topology.kinds[v]) {
            case VertexKind::Interior: {
                Vec3f q{0.0f, 0.0f, 0.0f}, r{0.0f, 0.0f, 0.0f};
                for (size_t k = 0; k < n; ++k) {
                    q = q + next.positions[faceBase + face[k]];
                    r = r + (s + level.positions[neighbour[k]]) * 0.5f;
                }
                const float valence = float(n);
                next.positions[v] = (q / valence + r / valence * 2.0f + s * (valence - 3.0f)) / valence;
                break;
            }
            case VertexKind::Boundary:
                next.positions[v] =
                    (level.positions[neighbour[0]] + s * 6.0f + level.positions[neighbour[n - 1]]) * 0.125f;
                break;
            case VertexKind::Unused:
            case VertexKind::Corner:
                next.positions[v] = s;
                break;
        }
    }
    // Each face of k corners into k quads (corner, its edge's point, the face point, the previous
    // edge's point), wound as the face.
    next.corners.reserve(4 * level.corners.size());
    next.faceStart.reserve(level.corners.size() + 1);
    const bool uvs = !level.cornerUvs.empty();
    if (uvs) next.cornerUvs.reserve(4 * level.corners.size());
    for (size_t f = 0; f < faceCount; ++f) {
        const uint32_t k = level.sizeOf(f);
        Vec2f centre{0.0f, 0.0f};
        if (uvs) {
            for (uint32_t i = 0; i < k; ++i) centre = centre + level.cornerUvs[level.corner(f, i)];
            centre = centre * (1.0f / float(k));
        }
        for (uint32_t i = 0; i < k; ++i) {
            const uint32_t c = level.corner(f, i), following = level.corner(f, i + 1),
                           previous = level.corner(f, i + k - 1);
            next.corners.insert(next.corners.end(),
                                {level.corners[c], uint32_t(edgeBase + topology.cornerEdge[c]),
                                 uint32_t(faceBase + f), uint32_t(edgeBase + topology.cornerEdge[previous])});
            next.faceStart.push_back(uint32_t(next.corners.size()));
            if (uvs) {
                const Vec2f uv = level.cornerUvs[c];
                next.cornerUvs.insert(next.cornerUvs.end(),
                                      {uv, (uv + level.cornerUvs[following]) * 0.5f, centre,
                                       (uv + level.cornerUvs[previous]) * 0.5f});
            }
        }
    }
    return next;
}

// The limit point and normal of every vertex of a level of quads; `facing[v]`, the sum of the
// normals of the quads at v, says which side is the front.
void limitOf(const Level& level, std::vector<Vec3f>& limit, std::vector<Vec3f>& normal) {
    const MeshTopology topology = topologyOfLevel(level);
    const size_t vertexCount = level.positions.size();
    std::vector<Vec3f> facing(vertexCount, Vec3f{0.0f, 0.0f, 0.0f});
    for (size_t f = 0; f < level.faceCount(); ++f) {
        const auto& p = level.positions;
        const uint32_t* c = &level.corners[level.faceStart[f]];
        const Vec3f n = cross(p[c[2]] - p[c[0]], p[c[3]] - p[c[1]]);  // the diagonals' cross product
        for (int k = 0; k < 4; ++k) facing[c[k]] = facing[c[k]] + n;
    }
    // The corner of quad f opposite vertex v.
    auto diagonal = [&](uint32_t f, uint32_t v) {
        const uint32_t* c = &level.corners[level.faceStart[f]];
        for (int k = 0; k < 4; ++k)
            if (c[k] == v) return c[(k + 2) % 4];
        return v;
    };
    limit = level.positions;
    normal.assign(vertexCount, Vec3f{0.0f, 0.0f, 1.0f});
    for (uint32_t v = 0; v < vertexCount; ++v) {
        const size_t n = topology.ringSize(v);
        const uint32_t* neighbour = topology.ring(v);
        const uint32_t* face = topology.ringFacesOf(v);
        const Vec3f s = level.positions[v];
        Vec3f tangentNormal{0.0f, 0.0f, 0.0f};
        if (topology.kinds[v] == VertexKind::Interior) {
            const double valence = double(n);
            Vec3f edgeSum{0.0f, 0.0f, 0.0f}, diagonalSum{0.0f, 0.0f, 0.0f};
            Vec3f t1{0.0f, 0.0f, 0.0f}, t2{0.0f, 0.0f, 0.0f};
            const double a = 1.0 + std::cos(2.0 * std::numbers::pi / valence) +
                             std::cos(std::numbers::pi / valence) *
                                 std::sqrt(2.0 * (9.0 + std::cos(2.0 * std::numbers::pi / valence)));
            for (size_t k = 0; k < n; ++k) {
                const Vec3f e = level.positions[neighbour[k]] - s,
                            d = level.positions[diagonal(face[k], v)] - s;
                edgeSum = edgeSum + e;
                diagonalSum = diagonalSum + d;
                const double angle = 2.0 * std::numbers::pi * double(k) / valence,
                             nextAngle = 2.0 * std::numbers::pi * double(k + 1) / valence;
                t1 = t1 + e * float(a * std::cos(angle)) + d * float(std::cos(angle) + std::cos(nextAngle));
                t2 = t2 + e * float(a * std::sin(angle)) + d * float(std::sin(angle) + std::sin(nextAngle));
            }
            // (n^2 s + 4 sum e + sum d) / (n (n + 5)), relative to s.
            limit[v] = s + (edgeSum * 4.0f + diagonalSum) / float(valence * (valence + 5.0));
            tangentNormal = cross(t1, t2);
        } else if (topology.kinds[v] == VertexKind::Boundary) {
            const Vec3f e0 = level.positions[neighbour[0]], e1 = level.positions[neighbour[n - 1]];
            limit[v] = (e0 + s * 4.0f + e1) / 6.0f;
            // Along the boundary, and into the surface: towards the mean of the ring's other points.
            Vec3f inside{0.0f, 0.0f, 0.0f};
            for (size_t k = 0; k + 1 < n; ++k) inside = inside + level.positions[diagonal(face[k], v)];
            for (size_t k = 1; k + 1 < n; ++k) inside = inside + level.positions[neighbour[k]];
            const Vec3f across = inside / float(2 * n - 3) - limit[v];
            tangentNormal = cross(e1 - e0, across);
        }
        Vec3f n3 = tangentNormal;
        if (!(lengthSquared(n3) > 0.0f) || !std::isfinite(lengthSquared(n3))) n3 = facing[v];
        if (dot(n3, facing[v]) < 0.0f) n3 = -n3;
        if (lengthSquared(n3) > 0.0f && std::isfinite(lengthSquared(n3))) normal[v] = normalize(n3);
    }
}

}  // namespace

TriangleMesh fanTriangulate(const PolygonMesh& polygons) {
    TriangleMesh mesh;
    mesh.positions = polygons.positions;
    mesh.uvs = polygons.uvs;
    size_t offset = 0;
    for (uint32_t size : polygons.faceSizes) {
        for (uint32_t k = 1; k + 1 < size; ++k)
            mesh.indices.insert(mesh.indices.end(), {polygons.corners[offset], polygons.corners[offset + k],
                                                     polygons.corners[offset + k + 1]});
        offset += size;
    }
    return mesh;
}

TriangleMesh catmullClarkSubdivide(const PolygonMesh& control, int levels) {
    if (levels < 1)
        throw InputError(fmt::format("Catmull-Clark subdivision needs at least 1 level, found {}", levels));
    // Triangles made: 2 per quad, each polygon of k corners k quads at the first level, 4 times
    // that at each next one. Bounded as Loop's, per control corner.
    const uint64_t corners = control.corners.size();
    const uint64_t allowed = std::min(limits::kMaxSubdividedTriangles,
                                      std::max(limits::kMinSubdividedTrianglesAllowed,
                                               corners * limits::kSubdividedTrianglesPerControlTriangle));
    uint64_t made = 2 * corners;
    for (int l = 1; l < levels && made <= allowed; ++l) made *= 4;
    if (made > allowed)
        throw InputError(fmt::format(
            "{} levels of subdivision would make more than {} triangles of the {} polygon corners given, "
            "penumbra's limit for this mesh (docs/limits.md: 4^5 a control corner, at least 2^22, at most "
            "2^26)",
            levels, allowed, corners));
    const std::vector<uint32_t> welded = weldedVertexIds(control.positions);
    Level level;
    level.positions = control.positions;
    level.corners.reserve(control.corners.size());
    for (uint32_t size : control.faceSizes) {
        if (size < 3) throw InputError(fmt::format("a polygon has {} corners: at least 3 are needed", size));
        const uint32_t start = uint32_t(level.corners.size());
        for (uint32_t k = 0; k < size; ++k) {
            const uint32_t vertex = control.corners[start + k];
            level.corners.push_back(welded[vertex]);
            if (!control.uvs.empty()) level.cornerUvs.push_back(control.uvs[vertex]);
        }
        level.faceStart.push_back(uint32_t(level.corners.size()));
    }
    for (int l = 0; l < levels; ++l) level = refineOnce(level);
    std::vector<Vec3f> limit, normal;
    limitOf(level, limit, normal);

    TriangleMesh mesh;
    // A vertex per distinct (vertex, uv): face-varying uvs split vertices along seams.
    CornerVertices ids;
    uint32_t quad[4];
    const bool uvs = !level.cornerUvs.empty();
    for (size_t f = 0; f < level.faceCount(); ++f) {
        for (uint32_t k = 0; k < 4; ++k) {
            const uint32_t c = level.faceStart[f] + k, vertex = level.corners[c];
            const Vec2f uv = uvs ? level.cornerUvs[c] : Vec2f{0.0f, 0.0f};
            bool added;
            quad[k] = ids.idOf(vertex, uv, added);
            if (added) {
                mesh.positions.push_back(limit[vertex]);
                mesh.normals.push_back(normal[vertex]);
                if (uvs) mesh.uvs.push_back(uv);
            }
        }
        mesh.indices.insert(mesh.indices.end(), {quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]});
    }
    return mesh;
}

}  // namespace penumbra
