// Triangle meshes from files: Wavefront OBJ (read with tinyobjloader), PLY in ASCII or binary and
// gzip-compressed PLY (read by our own checking walk, after zlib for .ply.gz), and placing a mesh
// in the world with a transform.
//
// tinyobjloader accepts broken files silently (it reads "abc" as 0), so each OBJ file is checked
// first by a small validator of our own that reports the line of what is wrong; PLY files are
// read by such a walk itself (assimp 5.2's reader, used before, hung or crashed on truncated
// files), which reports the line (ASCII) or the element (binary) of what is wrong.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/input_limits.h"
#include "core/transform.h"
#include "geometry/catmull_clark.h"
#include "geometry/triangle_mesh.h"

namespace penumbra {

// Reads the triangles of an OBJ, PLY or .ply.gz file (chosen by the file name's extension), in the
// file's own coordinates. Polygons are split into triangles. Normals and uvs are kept when every
// face corner has one; vertices that differ in them are split so one index buffer serves all.
// The mesh is named after the file; material and emission are left for the caller.
// Throws InputError naming the file (and the line when known) for a missing, unreadable,
// malformed or empty file, a face index out of range, or a non-finite vertex or normal.
// Degenerate (zero-area) triangles are kept. Only a regular file is read (not a FIFO or a device),
// of at most `maxBytes` as read (a .ply.gz once decompressed).
TriangleMesh importMesh(const std::filesystem::path& file, uint64_t maxBytes = limits::kMaxMeshFileBytes);

// The same for file contents already in memory; `fileForMessages` names them in errors.
TriangleMesh importObj(std::string_view text, const std::string& fileForMessages);
TriangleMesh importPly(std::string_view bytes, const std::string& fileForMessages);

// The polygons of the same files as they are, not split into triangles: the control mesh of a
// Catmull-Clark surface (geometry/catmull_clark.h). Uvs are kept when every corner has one (a vertex
// is split where its uvs differ); normals are not read (the surface's replace them). Errors as
// importMesh's.
PolygonMesh importPolygons(const std::filesystem::path& file, uint64_t maxBytes = limits::kMaxMeshFileBytes);
PolygonMesh importObjPolygons(std::string_view text, const std::string& fileForMessages);
PolygonMesh importPlyPolygons(std::string_view bytes, const std::string& fileForMessages);

// Moves a mesh into place: positions as points, normals with the inverse transpose (then
// renormalized). A mirroring transform (negative determinant) would turn the winding, and so the
// front face, inside out; each triangle's winding is swapped to keep front faces in front.
void transformMesh(TriangleMesh& mesh, const Transform& transform);

// Which side of a mesh file's triangles is the front (a "mesh_file"'s `front`).
enum class FrontSide : uint8_t {
    Winding,          // counter-clockwise (the default)
    Reversed,         // clockwise
    Normals,          // the side of each triangle's vertex normals (pbrt-v4's rule), else Winding
    ReversedNormals,  // the other side, the normals turned too (pbrt-v4's ReverseOrientation)
};
// Swaps the winding of the triangles whose front is not already on `side`.
void orientFaces(TriangleMesh& mesh, FrontSide side);

}  // namespace penumbra
