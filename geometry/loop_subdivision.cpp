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

namespace penumbra {

namespace {

constexpr uint32_t kNone = ~uint32_t(0);

using Face = std::array<uint32_t, 3>;
using CornerUvs = std::array<Vec2f, 3>;

// A mesh as the scheme sees it: triangles over welded vertices, uvs per triangle corner.
struct Level {
    std::vector<Vec3f> positions;
    std::vector<Face> faces;
    std::vector<CornerUvs> uvs;  // empty, or one per face
};

// For each vertex, the first vertex at a bitwise equal position.
std::vector<uint32_t> weldedIds(const std::vector<Vec3f>& positions) {
    struct Bits {
        uint32_t x, y, z;
        bool operator==(const Bits&) const = default;
    };
    struct HashBits {
        size_t operator()(const Bits& b) const {
            return std::hash<uint64_t>()((uint64_t(b.x) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(b.y) << 21) ^
                                         (uint64_t(b.z) * 0xC2B2AE3D27D4EB4Full));
        }
    };
    std::unordered_map<Bits, uint32_t, HashBits> first;
    first.reserve(positions.size());
    std::vector<uint32_t> ids(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        Bits bits{};
        const Vec3f p = positions[i];
        std::memcpy(&bits.x, &p.x, 4), std::memcpy(&bits.y, &p.y, 4), std::memcpy(&bits.z, &p.z, 4);
        ids[i] = first.try_emplace(bits, uint32_t(i)).first->second;
    }
    return ids;
}

// The mesh as a level, its triangles over the vertices `welded` gives (weldedIds).
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

// The edges of a level: edge e joins a < b, lies on faces[0] (and faces[1] when interior), and
// faceEdges[f][k] is the edge from corner k to corner k + 1 of face f.
struct Edges {
    struct Edge {
        uint32_t a, b;
        std::array<uint32_t, 2> faces{kNone, kNone};
    };
    std::vector<Edge> edges;
    std::vector<std::array<uint32_t, 3>> faceEdges;
};

Edges edgesOf(const Level& level) {
    std::vector<std::pair<uint64_t, uint32_t>> corners;  // (key of the edge, 3 * face + corner)
    corners.reserve(3 * level.faces.size());
    for (uint32_t f = 0; f < level.faces.size(); ++f)
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t a = level.faces[f][k], b = level.faces[f][(k + 1) % 3];
            corners.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), 3 * f + k});
        }
    std::sort(corners.begin(), corners.end());
    Edges out;
    out.faceEdges.resize(level.faces.size());
    for (size_t i = 0; i < corners.size();) {
        size_t j = i;
        while (j < corners.size() && corners[j].first == corners[i].first) ++j;
        const uint32_t a = uint32_t(corners[i].first >> 32), b = uint32_t(corners[i].first);
        if (j - i > 2)
            throw InputError(
                fmt::format("Loop subdivision needs a manifold mesh, but the edge between vertices {} and {} "
                            "is shared by {} triangles",
                            a, b, j - i));
        Edges::Edge edge{a, b};
        for (size_t c = i; c < j; ++c) {
            edge.faces[c - i] = corners[c].second / 3;
            out.faceEdges[corners[c].second / 3][corners[c].second % 3] = uint32_t(out.edges.size());
        }
        out.edges.push_back(edge);
        i = j;
    }
    return out;
}

enum class VertexKind : uint8_t { Unused, Interior, Boundary, Corner };

// Each vertex's neighbours in counter-clockwise order about its front side (as the triangles wind):
// a closed ring for an interior vertex, from one boundary neighbour to the other for a boundary vertex.
struct Rings {
    std::vector<VertexKind> kinds;
    std::vector<uint32_t> start;  // ring of v: neighbours[start[v], start[v + 1])
    std::vector<uint32_t> neighbours;
    size_t size(uint32_t v) const { return start[v + 1] - start[v]; }
    const uint32_t* of(uint32_t v) const { return neighbours.data() + start[v]; }
};

Rings ringsOf(const Level& level) {
    const size_t vertexCount = level.positions.size();
    // Every triangle corner at v gives the step b -> c of v's ring (b and c its other corners).
    struct Step {
        uint32_t v, b, c;
    };
    std::vector<Step> steps;
    steps.reserve(3 * level.faces.size());
    for (const Face& f : level.faces)
        for (int k = 0; k < 3; ++k) steps.push_back({f[k], f[(k + 1) % 3], f[(k + 2) % 3]});
    std::sort(steps.begin(), steps.end(),
              [](const Step& x, const Step& y) { return x.v != y.v ? x.v < y.v : x.b < y.b; });
    Rings rings;
    rings.kinds.assign(vertexCount, VertexKind::Unused);
    rings.start.assign(vertexCount + 1, 0);
    rings.neighbours.reserve(steps.size() + vertexCount);
    std::vector<uint32_t> ring, ends;
    for (size_t i = 0; i < steps.size();) {
        const uint32_t v = steps[i].v;
        size_t j = i;
        while (j < steps.size() && steps[j].v == v) ++j;
        const Step* first = &steps[i];
        const Step* last = &steps[j];
        // The step leaving neighbour b, found by binary search (steps are sorted by b).
        auto stepFrom = [&](uint32_t b) -> const Step* {
            const Step* s =
                std::lower_bound(first, last, b, [](const Step& x, uint32_t key) { return x.b < key; });
            if (s == last || s->b != b) return nullptr;
            if (s + 1 != last && s[1].b == b) return nullptr;  // two steps from b: not a disk
            return s;
        };
        // A boundary vertex's ring starts at the neighbour no step arrives at.
        ends.clear();
        for (const Step* s = first; s != last; ++s) ends.push_back(s->c);
        std::sort(ends.begin(), ends.end());
        uint32_t begin = kNone;
        int openings = 0;
        for (const Step* s = first; s != last; ++s)
            if (!std::binary_search(ends.begin(), ends.end(), s->b)) begin = s->b, ++openings;
        VertexKind kind = openings == 0 ? VertexKind::Interior : VertexKind::Boundary;
        if (openings > 1) kind = VertexKind::Corner;
        ring.clear();
        if (kind != VertexKind::Corner) {
            uint32_t b = kind == VertexKind::Interior ? first->b : begin;
            ring.push_back(b);
            for (size_t n = 0; n < size_t(last - first); ++n) {
                const Step* s = stepFrom(b);
                if (!s) {
                    kind = VertexKind::Corner;
                    break;
                }
                b = s->c;
                if (kind == VertexKind::Interior && b == ring.front()) break;
                ring.push_back(b);
            }
            // A disk's ring has one neighbour per triangle, a half-disk's one more.
            const size_t expected = size_t(last - first) + (kind == VertexKind::Boundary ? 1 : 0);
            if (kind != VertexKind::Corner && ring.size() != expected) kind = VertexKind::Corner;
        }
        if (kind == VertexKind::Corner) ring.clear();
        rings.kinds[v] = kind;
        rings.start[v] = uint32_t(rings.neighbours.size());
        rings.neighbours.insert(rings.neighbours.end(), ring.begin(), ring.end());
        for (uint32_t u = v + 1; u <= vertexCount && (j == steps.size() || u <= steps[j].v); ++u)
            rings.start[u] = uint32_t(rings.neighbours.size());
        i = j;
    }
    return rings;
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
    const Edges edges = edgesOf(level);
    const Rings rings = ringsOf(level);
    const size_t vertexCount = level.positions.size();
    Level next;
    next.positions.resize(vertexCount + edges.edges.size());
    // Even vertices: the old ones, smoothed.
    for (uint32_t v = 0; v < vertexCount; ++v) {
        const Vec3f p = level.positions[v];
        const size_t n = rings.size(v);
        switch (rings.kinds[v]) {
            case VertexKind::Interior: {
                const double beta = loopBeta(n);
                next.positions[v] =
                    p * float(1.0 - double(n) * beta) + positionSum(level, rings.of(v), n) * float(beta);
                break;
            }
            case VertexKind::Boundary:
                next.positions[v] =
                    p * 0.75f +
                    (level.positions[rings.of(v)[0]] + level.positions[rings.of(v)[n - 1]]) * 0.125f;
                break;
            case VertexKind::Unused:
            case VertexKind::Corner:
                next.positions[v] = p;
                break;
        }
    }
    // Odd vertices: one per edge.
    auto opposite = [&](uint32_t face, const Edges::Edge& e) {
        const Face& f = level.faces[face];
        for (uint32_t c : f)
            if (c != e.a && c != e.b) return c;
        return e.a;  // a degenerate triangle repeats a vertex
    };
    for (size_t e = 0; e < edges.edges.size(); ++e) {
        const Edges::Edge& edge = edges.edges[e];
        const Vec3f a = level.positions[edge.a], b = level.positions[edge.b];
        if (edge.faces[1] == kNone) {
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
        const std::array<uint32_t, 3> m{uint32_t(vertexCount + edges.faceEdges[f][0]),
                                        uint32_t(vertexCount + edges.faceEdges[f][1]),
                                        uint32_t(vertexCount + edges.faceEdges[f][2])};
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
    struct Key {
        uint32_t vertex;
        Vec2f uv;
        bool operator==(const Key& o) const { return vertex == o.vertex && uv.x == o.uv.x && uv.y == o.uv.y; }
    };
    struct HashKey {
        size_t operator()(const Key& k) const {
            uint32_t u, v;
            std::memcpy(&u, &k.uv.x, 4), std::memcpy(&v, &k.uv.y, 4);
            return std::hash<uint64_t>()((uint64_t(k.vertex) << 32) ^ (uint64_t(u) * 0x9E3779B97F4A7C15ull) ^
                                         v);
        }
    };
    std::unordered_map<Key, uint32_t, HashKey> ids;
    ids.reserve(level.positions.size());
    mesh.indices.reserve(3 * level.faces.size());
    for (size_t f = 0; f < level.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const Key key{level.faces[f][k], level.uvs[f][k]};
            const auto [it, added] = ids.try_emplace(key, uint32_t(mesh.positions.size()));
            if (added) {
                mesh.positions.push_back(level.positions[key.vertex]);
                mesh.uvs.push_back(key.uv);
            }
            mesh.indices.push_back(it->second);
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
    Level level = levelOf(control, weldedIds(control.positions));
    for (int l = 0; l < levels; ++l) level = refineOnce(level);
    return meshOf(std::move(level), control);
}

TriangleMesh moveToLoopLimit(const TriangleMesh& mesh) {
    const std::vector<uint32_t> welded = weldedIds(mesh.positions);
    const Level level = levelOf(mesh, welded);
    const Rings rings = ringsOf(level);
    // The sum of the (area-weighted) normals of the triangles at each vertex: which side is the front.
    std::vector<Vec3f> faceNormals(level.positions.size(), Vec3f{0.0f, 0.0f, 0.0f});
    for (const Face& f : level.faces) {
        const auto& p = level.positions;
        const Vec3f n = cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
        for (uint32_t v : f) faceNormals[v] = faceNormals[v] + n;
    }
    std::vector<Vec3f> limit(level.positions), normal(level.positions.size(), Vec3f{0.0f, 0.0f, 1.0f});
    for (uint32_t v = 0; v < level.positions.size(); ++v) {
        const size_t n = rings.size(v);
        const uint32_t* r = rings.of(v);
        const Vec3f p = level.positions[v];
        Vec3f tangentNormal{0.0f, 0.0f, 0.0f};
        switch (rings.kinds[v]) {
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
