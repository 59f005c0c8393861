// The topology the subdivision schemes (geometry/loop_subdivision.h, geometry/catmull_clark.h) need
// of a mesh of polygons over welded vertices (geometry/vertex_welding.h): its edges, each with the
// one or two faces it borders, and each vertex's ring of neighbours in order about its front side.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace penumbra {

enum class VertexKind : uint8_t {
    Unused,    // on no face
    Interior,  // its faces make a disk: a closed ring
    Boundary,  // a half-disk: a ring from one boundary neighbour to the other
    Corner,    // anything else (fans meeting at a point, a dangling edge chain)
};

struct MeshTopology {
    static constexpr uint32_t kNoFace = ~uint32_t(0);
    // Edge e joins a < b and borders faces[0] (and faces[1] when it is interior).
    struct Edge {
        uint32_t a, b;
        std::array<uint32_t, 2> faces{kNoFace, kNoFace};
    };
    std::vector<Edge> edges;
    std::vector<uint32_t> cornerEdge;  // the edge from corner c to the next corner of its face

    // Vertex v's ring, counter-clockwise about its front side (as the faces wind): its neighbours
    // ringNeighbours[ringStart[v], ringStart[v + 1]) and, at the same places, the face between each
    // neighbour and the next (kNoFace after a boundary ring's last neighbour, which has one more
    // neighbour than faces). Empty for corners and unused vertices.
    std::vector<VertexKind> kinds;
    std::vector<uint32_t> ringStart, ringNeighbours, ringFaces;
    size_t ringSize(uint32_t v) const { return ringStart[v + 1] - ringStart[v]; }
    const uint32_t* ring(uint32_t v) const { return ringNeighbours.data() + ringStart[v]; }
    const uint32_t* ringFacesOf(uint32_t v) const { return ringFaces.data() + ringStart[v]; }
};

// The topology of `vertexCount` vertices under faces whose corners are
// corners[faceStart[f], faceStart[f + 1]). Throws InputError when an edge borders more than two
// faces ("{scheme} subdivision needs a manifold mesh, ... shared by 3 {faceWord}").
MeshTopology topologyOf(const std::vector<uint32_t>& faceStart, const std::vector<uint32_t>& corners,
                        size_t vertexCount, std::string_view scheme, std::string_view faceWord);

}  // namespace penumbra
