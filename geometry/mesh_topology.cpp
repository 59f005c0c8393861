#include "geometry/mesh_topology.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"

namespace penumbra {

namespace {

// Face f's corner k, taken modulo its size, as an index into the corners.
uint32_t cornerOf(const std::vector<uint32_t>& faceStart, size_t f, uint32_t k) {
    return faceStart[f] + k % (faceStart[f + 1] - faceStart[f]);
}

void findEdges(const std::vector<uint32_t>& faceStart, const std::vector<uint32_t>& corners,
               std::string_view scheme, std::string_view faceWord, MeshTopology& out) {
    const size_t faceCount = faceStart.size() - 1;
    std::vector<std::pair<uint64_t, uint32_t>> keyed;  // (key of the edge, corner)
    keyed.reserve(corners.size());
    std::vector<uint32_t> faceOfCorner(corners.size());
    for (uint32_t f = 0; f < faceCount; ++f)
        for (uint32_t k = 0; k < faceStart[f + 1] - faceStart[f]; ++k) {
            const uint32_t c = cornerOf(faceStart, f, k);
            const uint32_t a = corners[c], b = corners[cornerOf(faceStart, f, k + 1)];
            keyed.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), c});
            faceOfCorner[c] = f;
        }
    std::sort(keyed.begin(), keyed.end());
    out.cornerEdge.resize(corners.size());
    for (size_t i = 0; i < keyed.size();) {
        size_t j = i;
        while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
        const uint32_t a = uint32_t(keyed[i].first >> 32), b = uint32_t(keyed[i].first);
        if (j - i > 2)
            throw InputError(
                fmt::format("{} subdivision needs a manifold mesh, but the edge between vertices {} and {} "
                            "is shared by {} {}",
                            scheme, a, b, j - i, faceWord));
        MeshTopology::Edge edge{a, b};
        for (size_t c = i; c < j; ++c) {
            edge.faces[c - i] = faceOfCorner[keyed[c].second];
            out.cornerEdge[keyed[c].second] = uint32_t(out.edges.size());
        }
        out.edges.push_back(edge);
        i = j;
    }
}

void findRings(const std::vector<uint32_t>& faceStart, const std::vector<uint32_t>& corners,
               size_t vertexCount, MeshTopology& out) {
    const size_t faceCount = faceStart.size() - 1;
    // Every corner at v gives the step next -> previous of v's ring, across its face.
    struct Step {
        uint32_t v, from, to, face;
    };
    std::vector<Step> steps;
    steps.reserve(corners.size());
    for (uint32_t f = 0; f < faceCount; ++f) {
        const uint32_t size = faceStart[f + 1] - faceStart[f];
        for (uint32_t k = 0; k < size; ++k)
            steps.push_back({corners[cornerOf(faceStart, f, k)], corners[cornerOf(faceStart, f, k + 1)],
                             corners[cornerOf(faceStart, f, k + size - 1)], f});
    }
    std::sort(steps.begin(), steps.end(),
              [](const Step& x, const Step& y) { return x.v != y.v ? x.v < y.v : x.from < y.from; });
    out.kinds.assign(vertexCount, VertexKind::Unused);
    out.ringStart.assign(vertexCount + 1, 0);
    out.ringNeighbours.reserve(steps.size() + vertexCount);
    out.ringFaces.reserve(steps.size() + vertexCount);
    std::vector<uint32_t> ends, ring, ringFaces;
    for (size_t i = 0; i < steps.size();) {
        const uint32_t v = steps[i].v;
        size_t j = i;
        while (j < steps.size() && steps[j].v == v) ++j;
        const Step* first = &steps[i];
        const Step* last = &steps[j];
        // The step leaving neighbour `from`, found by binary search (steps are sorted by it).
        auto stepFrom = [&](uint32_t from) -> const Step* {
            const Step* s =
                std::lower_bound(first, last, from, [](const Step& x, uint32_t key) { return x.from < key; });
            if (s == last || s->from != from) return nullptr;
            if (s + 1 != last && s[1].from == from) return nullptr;  // two steps from one neighbour: no disk
            return s;
        };
        // A boundary vertex's ring starts at the neighbour no step arrives at.
        ends.clear();
        for (const Step* s = first; s != last; ++s) ends.push_back(s->to);
        std::sort(ends.begin(), ends.end());
        uint32_t begin = MeshTopology::kNoFace;
        int openings = 0;
        for (const Step* s = first; s != last; ++s)
            if (!std::binary_search(ends.begin(), ends.end(), s->from)) begin = s->from, ++openings;
        VertexKind kind = openings == 0 ? VertexKind::Interior : VertexKind::Boundary;
        if (openings > 1) kind = VertexKind::Corner;
        ring.clear(), ringFaces.clear();
        if (kind != VertexKind::Corner) {
            uint32_t from = kind == VertexKind::Interior ? first->from : begin;
            ring.push_back(from);
            for (size_t n = 0; n < size_t(last - first); ++n) {
                const Step* s = stepFrom(from);
                if (!s) {
                    kind = VertexKind::Corner;
                    break;
                }
                ringFaces.push_back(s->face);
                from = s->to;
                if (kind == VertexKind::Interior && from == ring.front()) break;
                ring.push_back(from);
            }
            // A disk's ring has one neighbour per face, a half-disk's one more.
            const size_t expected = size_t(last - first) + (kind == VertexKind::Boundary ? 1 : 0);
            if (kind != VertexKind::Corner &&
                (ring.size() != expected || ringFaces.size() != size_t(last - first)))
                kind = VertexKind::Corner;
        }
        if (kind == VertexKind::Corner) ring.clear(), ringFaces.clear();
        ringFaces.resize(ring.size(), MeshTopology::kNoFace);
        out.kinds[v] = kind;
        out.ringStart[v] = uint32_t(out.ringNeighbours.size());
        out.ringNeighbours.insert(out.ringNeighbours.end(), ring.begin(), ring.end());
        out.ringFaces.insert(out.ringFaces.end(), ringFaces.begin(), ringFaces.end());
        for (uint32_t u = v + 1; u <= vertexCount && (j == steps.size() || u <= steps[j].v); ++u)
            out.ringStart[u] = uint32_t(out.ringNeighbours.size());
        i = j;
    }
}

}  // namespace

MeshTopology topologyOf(const std::vector<uint32_t>& faceStart, const std::vector<uint32_t>& corners,
                        size_t vertexCount, std::string_view scheme, std::string_view faceWord) {
    MeshTopology topology;
    findEdges(faceStart, corners, scheme, faceWord, topology);
    findRings(faceStart, corners, vertexCount, topology);
    return topology;
}

}  // namespace penumbra
