// Loop subdivision surfaces (Charles Loop, "Smooth Subdivision Surfaces Based on Triangles", 1987),
// with the boundary rules pbrt-v4's `loopsubdiv` shape uses (a boundary is refined as a cubic
// B-spline of its own vertices, independent of the interior; its limit points are the B-spline's,
// where pbrt-v4's differ slightly: loop_subdivision.cpp). A control mesh is refined a given
// number of levels at load time, then every vertex is moved to its point on the limit surface and
// given the limit surface's normal there: what both traversal backends then see is an ordinary
// triangle mesh, so both render the same surface.
//
// The mesh's topology is that of its positions: vertices at bitwise equal positions are one vertex
// (a mesh file splits vertices where uvs or normals differ). The control mesh's normals are
// replaced by the limit normals; its uvs are interpolated linearly over each control triangle.
// Vertices whose neighbourhood is neither a disk nor a half-disk (where two fans meet at a point,
// or at the end of a dangling edge chain) keep their position, as corners.
#pragma once

#include <cstdint>

#include "geometry/triangle_mesh.h"

namespace penumbra {

// `levels` steps of Loop's refinement, each splitting every triangle into four (vertex i of the
// input stays vertex i), without moving to the limit. Throws InputError when an edge is shared by
// more than two triangles (the scheme needs a manifold mesh) or when the result would exceed
// the limit core/input_limits.h sets for a mesh of its size.
TriangleMesh refineLoop(const TriangleMesh& control, int levels);

// Every vertex moved to its limit position, with the limit surface's unit normal (facing the side
// the triangles' winding faces).
TriangleMesh moveToLoopLimit(const TriangleMesh& mesh);

// What a subdivision surface renders: refineLoop, then moveToLoopLimit.
TriangleMesh loopSubdivide(const TriangleMesh& control, int levels);

}  // namespace penumbra
