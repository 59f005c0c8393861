// The limits on what penumbra reads, in one place (docs/limits.md lists them with the reasons).
// Each is generous for any real scene; beyond it an input is refused with a message, rather than
// hanging, overflowing or exhausting memory.
#pragma once

#include <cstddef>
#include <cstdint>

namespace penumbra::limits {

// Image width and height (scene "film.resolution", --res, a film's EXR windows).
constexpr int kMaxImageSide = 1 << 16;
// Texels of an image read whole into memory (an environment map): 2^27, 1.5 GiB of RGB floats.
constexpr int64_t kMaxImageTexels = int64_t(1) << 27;
// Texels of an image texture, at every MIP level a file holds (8192 x 8192): OpenImageIO reads an
// untiled image, or one it must linearise, whole, so beyond this one file could take more than the
// tile cache's 2 GiB (at the limit an untiled RGBA float EXR took 1.8 GB of peak memory, an RGBA
// PNG 1.2 GB). Checked from the header, before any pixel is allocated.
constexpr int64_t kMaxTextureTexels = int64_t(1) << 26;
// Channels of any image read, and its values (texels x channels): every channel is decoded and
// cached, though at most three are used, so the values are limited to those of the largest RGBA
// image (4 x kMaxTextureTexels for a texture, 4 x kMaxImageTexels for an environment map).
constexpr int kMaxImageChannels = 1024;
constexpr int64_t kMaxValuesPerTexel = 4;
// Chunks (scanline blocks or tiles, all parts and levels) of an OpenEXR image: OpenEXR allocates
// a table of their offsets when it opens a file, 8 bytes each (32 MiB at this limit; an 8192 x
// 8192 texture in 64 x 64 tiles with its MIP levels has 21,846).
constexpr int64_t kMaxExrChunks = int64_t(1) << 22;

// Bytes of a scene file (JSON): parsing takes about four times its size in memory.
constexpr uint64_t kMaxSceneFileBytes = uint64_t(256) << 20;

// pbrt-v4 scenes (formats/pbrt), where Include, object instances and nesting let a small file ask
// for unbounded work or memory. Files read for one scene (the scene file, and each Include or
// Import every time it is read): 13 files of 10 Includes each once meant 10^12 readings.
constexpr int kMaxPbrtFileReads = 16384;
// Bytes of pbrt text read for one scene, counted the same way (each file is also within
// kMaxSceneFileBytes): four JSON scene files' worth.
constexpr uint64_t kMaxPbrtTextBytes = uint64_t(1) << 30;
// Of that, the text of files read again (their second and later readings): as much as the distinct
// files hold, or 16 MiB if that is more. A reading adds nothing to the input, but the scene made of
// it takes about nine times the text: a 64 KB mesh read 16384 times would take 10 GB.
constexpr uint64_t kMinPbrtRereadBytes = uint64_t(16) << 20;
// AttributeBegin, TransformBegin and ObjectBegin open at once: each keeps a copy of the graphics
// state (10^6 of them took 500 MB); exporters nest one level per node of a scene graph.
constexpr int kMaxPbrtNesting = 4096;
// Values (numbers, names) in one texture a pbrt file builds of other textures: each use of a
// texture copies it, so 40 Texture lines each naming the one before twice would hold 2^40.
constexpr size_t kMaxPbrtTextureValues = 4096;
// Shapes placed by ObjectInstance (one instance per mesh of the object, or a copy of a sphere, an
// emitter or a moving shape; a copied mesh counts its triangles): one per 16 bytes of the scene's
// text, as many as writing each out as `Shape "sphere"` would give, and at least 2^16 (about 110
// MB). A 54 KB file once placed 10^6 spheres.
constexpr int kPbrtTextBytesPerPlacedShape = 16;
constexpr int64_t kMinPbrtPlacedShapes = int64_t(1) << 16;

// Bytes of a spectrum file a pbrt scene names (pbrt-v4's .spd: wavelength and value pairs as text):
// measured ones are a few kilobytes. Each file is read once per scene.
constexpr uint64_t kMaxSpectrumFileBytes = uint64_t(1) << 20;

// Bytes of a mesh file as read: an OBJ or PLY file, or a .ply.gz once decompressed.
constexpr uint64_t kMaxMeshFileBytes = uint64_t(4) << 30;

// IES photometric files (lights/ies_profile.h): bytes of a file, and angles of each kind in its
// table. Real files are a few kilobytes with at most a few hundred angles of each; the limits keep
// a table (4096 x 4096 values, four times that once a quadrant symmetry is unfolded) within a few
// hundred megabytes, and the table grows only with the numbers the file actually holds.
constexpr uint64_t kMaxIesFileBytes = uint64_t(16) << 20;
constexpr int kMaxIesAngles = 4096;

// Heterogeneous media's grids (media/openvdb_grid.h, media/nanovdb_grid.h). Bytes of an OpenVDB or
// NanoVDB file: a NanoVDB reader holds the chosen grid's bytes in memory, as the file stores them
// (a grid at the voxel limit below, every voxel in a leaf, takes about 1.1 GiB).
constexpr uint64_t kMaxVolumeFileBytes = uint64_t(4) << 30;
// Voxels of the lattice a grid is densified into (the box of its active voxels): 2^28, 1 GiB of
// floats (645^3, or a 1024 x 512 x 512 cloud). A file of a few kilobytes can place two voxels far
// apart, or one active tile over 4096^3 voxels: the lattice is sized, and refused, before anything
// is allocated for it.
constexpr int64_t kMaxGridVoxels = int64_t(1) << 28;

// Bytes of a measured BRDF (.bsdf, materials/measured_bsdf_reader.h): the RGL database's spectral
// files are tens of megabytes. The tables built from one take at most about three times its size.
constexpr uint64_t kMaxMeasuredBsdfFileBytes = uint64_t(1) << 30;

// Magnitude of a coordinate or a length in a scene (positions, corners, centres, radii, lens
// sizes), after transforms: below it, squared distances stay within a 32-bit float (1e36 < 3.4e38);
// beyond it, intersection tests overflow and geometry would silently vanish.
constexpr float kMaxCoordinate = 1e18f;

// Reconstruction filter radius, in pixels ("film.filter.radius"): a wider filter spreads a pixel's
// samples over hundreds of others' and, at 3e38, off the image altogether.
constexpr float kMaxFilterRadius = 64.0f;

// Lattice points along each axis of a participating medium's grid given in the scene file
// ("density.resolution"): the values themselves are bounded by the file's size.
constexpr int kMaxGridSide = 4096;

// Scattering events per path (scene "integrator.max_depth" and "roulette_start").
constexpr int kMaxPathDepth = 1024;

// Corners of one OBJ face: tinyobjloader splits polygons by ear clipping, in time that grows with
// the square of the corners; 1024 take no time worth noticing (bench/README.md, "Speed tricks").
constexpr int kMaxObjFaceCorners = 1024;

// Triangles a subdivision surface is refined into (geometry/loop_subdivision.h): each level makes
// four of one, so a small file asking for many levels would otherwise ask for any amount of memory.
// The refined triangles are bounded by the input: 4^5 per control triangle (five levels of any
// mesh), or 2^22 if that is more (a small mesh refined finely, about 250 MB), and never more than
// 2^26 (1.5 GiB with their vertices, and a traversal structure several more).
constexpr uint64_t kSubdividedTrianglesPerControlTriangle = uint64_t(1) << 10;
constexpr uint64_t kMinSubdividedTrianglesAllowed = uint64_t(1) << 22;
constexpr uint64_t kMaxSubdividedTriangles = uint64_t(1) << 26;

// Worker threads (--threads). TBB's arena teardown crashes beyond 65536; no machine has 4096 cores.
constexpr int kMaxThreads = 4096;

}  // namespace penumbra::limits
