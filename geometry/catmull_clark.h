// Catmull-Clark subdivision surfaces (E. Catmull and J. Clark, "Recursively generated B-spline
// surfaces on arbitrary topological meshes", 1978), for control meshes of polygons of any size
// (an OBJ modeller's quads). Refined at load a given number of levels, then every vertex moved to
// its point on the limit surface with the limit surface's normal, as Loop surfaces are
// (geometry/loop_subdivision.h), and each quad split into two triangles: both traversal backends
// then trace the same triangle mesh. (Embree's own subdivision geometry tessellates on the fly
// with its own rules and edge levels; our BVH could not trace the same surface.)
//
// Rules: face points are their polygon's centroid; an interior edge's point is the average of its
// ends and its two faces' points, a boundary edge's its midpoint; an interior vertex of valence n
// moves to (Q + 2 R + (n - 3) S) / n (Q the average of its faces' points, R of its edges'
// midpoints); a boundary vertex to the cubic B-spline of its boundary, (e0 + 6 S + e1) / 8; a
// vertex of a single face, or one where the mesh is not a disk or a half-disk, stays where it is
// (a sharp corner, as OpenSubdiv's default boundary interpolation keeps a valence-2 corner). After
// one level every face is a quad, and the limit masks of Halstead, Kass and DeRose ("Efficient,
// fair interpolation using Catmull-Clark surfaces", 1993) give positions and tangents: an interior
// vertex's limit point (n^2 S + 4 sum e_j + sum d_j) / (n (n + 5)) over its edge neighbours e_j and
// its quads' diagonal corners d_j, a boundary vertex's (e0 + 4 S + e1) / 6. Uvs are interpolated
// linearly over each control polygon (face-varying: a vertex is split where its uvs differ).
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec.h"
#include "geometry/triangle_mesh.h"

namespace penumbra {

// A control mesh of polygons.
struct PolygonMesh {
    std::vector<Vec3f> positions;
    std::vector<Vec2f> uvs;           // optional, one per position
    std::vector<uint32_t> faceSizes;  // the corners of each polygon, 3 or more
    std::vector<uint32_t> corners;    // the polygons' vertex indices, faceSizes[f] for face f, in order
};

// The polygons as triangle fans (corner 0 with each later pair), for a mesh that is not subdivided.
TriangleMesh fanTriangulate(const PolygonMesh& polygons);

// `levels` (>= 1) steps of refinement, then the limit surface's points and normals, as triangles
// facing the side the polygons' winding faces (the geometry alone: material, emission and the rest
// are the caller's). Throws InputError when an edge is shared by more than two faces (the scheme needs a
// manifold mesh), a face has fewer than 3 corners, or the result would exceed the limit
// core/input_limits.h sets for a mesh of its size.
TriangleMesh catmullClarkSubdivide(const PolygonMesh& control, int levels);

}  // namespace penumbra
