#include "media/nanovdb_grid.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "media/grid_lattice.h"

namespace penumbra {

namespace {

// The layout, from NanoVDB.h and util/IO.h of NanoVDB 32.3.3 (pbrt-v4's) and 32.4.2 (OpenVDB 10),
// which agree for float grids: byte offsets within each structure, little-endian throughout. A file
// is one or more segments: a header, the meta data of each of its grids (each followed by the
// grid's name), then each grid's buffer as it lies in memory.
constexpr uint64_t kMagic = 0x304244566f6e614eull;          // "NanoVDB0"
constexpr uint64_t kMagicSwapped = 0x4e616e6f56444230ull;   // the same, big-endian
constexpr uint64_t kMagicGrid32_6 = 0x314244566f6e614eull;  // "NanoVDB1": NanoVDB 32.6 and later
constexpr uint64_t kMagicFile32_6 = 0x324244566f6e614eull;  // "NanoVDB2"
constexpr uint32_t kMajorVersion = 32;

// io::Header: magic (u64), version (u32: major << 21 | minor << 10 | patch), grid count (u16),
// codec (u16: 0 NONE, 1 ZIP, 2 BLOSC).
constexpr uint64_t kHeaderBytes = 16;
// io::MetaData, then the name: grid size in memory and on disk (u64 at 0 and 8), grid type (u32 at
// 32), name size (u32 at 136, its '\0' included).
constexpr uint64_t kMetaGridSize = 0, kMetaFileSize = 8, kMetaGridType = 32, kMetaNameSize = 136,
                   kMetaBytes = 176;
// GridData: magic (u64 at 0), version (u32 at 16), grid size (u64 at 32), Map at 296 (its 3 x 3
// double matrix at +88, row by row as applyMap multiplies, its double translation at +232), grid
// type (u32 at 636).
constexpr uint64_t kGridMagic = 0, kGridVersion = 16, kGridSize = 32, kGridMatrix = 296 + 88,
                   kGridTranslation = 296 + 232, kGridType = 636, kGridBytes = 672;
// TreeData, right after GridData: byte offsets from the TreeData of the first leaf, lower, upper
// and root node (u64 x 4), and the counts of leaf, lower and upper nodes (u32 x 3). The nodes of
// each level lie in one array.
constexpr uint64_t kTreeNodeOffsets = 0, kTreeNodeCounts = 32, kTreeBytes = 64;
// RootData<float>: the table size (u32 at 24), the background (f32 at 28); its tiles follow it:
// key (u64: x, y, z of the origin >> 12, 21 bits each, x highest), child (i64 offset from the
// RootData, 0 for none), state (u32, active when not 0), value (f32).
constexpr uint64_t kRootTableSize = 24, kRootBackground = 28, kRootBytes = 64;
constexpr uint64_t kTileKey = 0, kTileChild = 8, kTileState = 16, kTileValue = 20, kTileBytes = 32;
// InternalData<float, LOG2DIM>: bounding box, flags, value mask, child mask (one bit an entry, in
// u64 words), statistics, then the table of 8-byte entries: a float value or an i64 offset of the
// child from this node. Entry n is at local (n >> 2 LOG2DIM, (n >> LOG2DIM) & mask, n & mask).
struct InternalLayout {
    int log2Dim,
        childLog2;  // 5 and 7 for the upper nodes (32^3 children of 128^3 voxels), 4 and 3 for the lower
    uint64_t valueMask, childMask, table, bytes;
    const char* name;
};
constexpr InternalLayout kUpper{5, 7, 32, 32 + 4096, 64 + 8192, 64 + 8192 + 8 * 32768, "upper internal node"};
constexpr InternalLayout kLower{4, 3, 32, 32 + 512, 64 + 1024, 64 + 1024 + 8 * 4096, "lower internal node"};
// LeafData<float>: value mask (8 u64 words at 16), then 512 floats at 96.
constexpr uint64_t kLeafValueMask = 16, kLeafValues = 96, kLeafBytes = 2144;
constexpr uint64_t kNodeBytes[3] = {kLeafBytes, kLower.bytes, kUpper.bytes};
constexpr const char* kNodeNames[3] = {"leaf node", "lower internal node", "upper internal node"};

constexpr uint32_t kTypeFloat = 1;
const char* typeName(uint32_t type) {
    // GridType of NanoVDB 32.3 (32.4 appends index types).
    static const char* const names[] = {"unknown", "float", "double", "int16",  "int32", "int64", "Vec3f",
                                        "Vec3d",   "mask",  "half",   "uint32", "bool",  "RGBA8", "Fp4",
                                        "Fp8",     "Fp16",  "FpN",    "Vec4f",  "Vec4d"};
    return type < std::size(names) ? names[type] : "of a type this reader does not know";
}

std::string describeVersion(uint32_t version) {
    return std::to_string(version >> 21) + "." + std::to_string((version >> 10) & 2047) + "." +
           std::to_string(version & 1023);
}

bool versionRead(uint32_t version) {
    const uint32_t major = version >> 21, minor = (version >> 10) & 2047;
    return major == kMajorVersion && (minor == 3 || minor == 4);
}

std::string quotedName(const std::string& name) {
    // Names come from the file: a long one is cut, for the message's sake.
    return "\"" + (name.size() > 64 ? name.substr(0, 64) + "..." : name) + "\"";
}

// Reads `n` bytes at `offset` of the input into `out`; the caller has checked they are within it.
using ReadAt = std::function<void(uint64_t offset, void* out, size_t n)>;

template <typename T>
T readValue(const ReadAt& readAt, uint64_t offset) {
    T value;
    readAt(offset, &value, sizeof value);
    return value;
}

struct GridEntry {
    std::string name;
    uint32_t type = 0;
    uint16_t codec = 0;
    uint64_t gridSize = 0, fileSize = 0, offset = 0;
};

// The grids of every segment, where their buffers are, checked to lie within the file's `size` bytes.
std::vector<GridEntry> readDirectory(uint64_t size, const ReadAt& readAt, const std::string& file) {
    std::vector<GridEntry> grids;
    uint64_t at = 0;
    while (at < size) {
        if (size - at < kHeaderBytes) {
            if (at == 0)
                throwFileError(file, "is not a NanoVDB file: it is " + std::to_string(size) +
                                         " bytes, fewer than the 16 of a NanoVDB file header");
            throwFileError(file, "truncated NanoVDB file: " + std::to_string(size - at) +
                                     " bytes after the grids at byte " + std::to_string(at) +
                                     ", too few for another segment's header (16 bytes)");
        }
        const auto magic = readValue<uint64_t>(readAt, at);
        const auto version = readValue<uint32_t>(readAt, at + 8);
        const auto count = readValue<uint16_t>(readAt, at + 12);
        const auto codec = readValue<uint16_t>(readAt, at + 14);
        const std::string where = at == 0 ? "" : " (the segment at byte " + std::to_string(at) + ")";
        if (magic == kMagicSwapped)
            throwFileError(file,
                           "is a big-endian NanoVDB file" + where + "; penumbra reads little-endian ones");
        if (magic == kMagicGrid32_6 || magic == kMagicFile32_6)
            throwFileError(file,
                           "is a NanoVDB file of version 32.6 or later (OpenVDB 11 or later)" + where +
                               "; penumbra reads NanoVDB 32.3 and 32.4 files (pbrt-v4's, OpenVDB 9 and 10)");
        if (magic != kMagic)
            throwFileError(
                file, at == 0 ? "is not a NanoVDB file: it does not start with the magic number \"NanoVDB0\""
                              : "bytes at " + std::to_string(at) +
                                    " after the last grid are not a NanoVDB segment header (magic number "
                                    "\"NanoVDB0\")");
        if (!versionRead(version))
            throwFileError(file,
                           "is a NanoVDB file of version " + describeVersion(version) + where +
                               "; penumbra reads NanoVDB 32.3 and 32.4 files (pbrt-v4's, OpenVDB 9 and 10)");
        if (count == 0) throwFileError(file, "NanoVDB segment" + where + " holds no grids");
        if (codec > 2)
            throwFileError(file, "NanoVDB segment" + where + " has an unknown codec (" +
                                     std::to_string(codec) +
                                     "); penumbra reads uncompressed NanoVDB files (codec NONE)");
        at += kHeaderBytes;
        const size_t first = grids.size();
        for (int g = 0; g < count; ++g) {
            if (size - at < kMetaBytes)
                throwFileError(file, "truncated NanoVDB file: the meta data of grid " +
                                         std::to_string(grids.size() + 1) + " at byte " + std::to_string(at) +
                                         " ends past the file's " + std::to_string(size) + " bytes");
            GridEntry grid;
            grid.gridSize = readValue<uint64_t>(readAt, at + kMetaGridSize);
            grid.fileSize = readValue<uint64_t>(readAt, at + kMetaFileSize);
            grid.type = readValue<uint32_t>(readAt, at + kMetaGridType);
            grid.codec = codec;
            const auto nameSize = readValue<uint32_t>(readAt, at + kMetaNameSize);
            at += kMetaBytes;
            if (nameSize == 0)
                throwFileError(file, "NanoVDB grid " + std::to_string(grids.size() + 1) +
                                         "'s name is empty (0 bytes, "
                                         "not even its '\\0')");
            if (nameSize > size - at)
                throwFileError(file, "truncated NanoVDB file: grid " + std::to_string(grids.size() + 1) +
                                         "'s name (" + std::to_string(nameSize) + " bytes at byte " +
                                         std::to_string(at) + ") ends past its " + std::to_string(size) +
                                         " bytes");
            grid.name.resize(nameSize);
            readAt(at, grid.name.data(), nameSize);
            const size_t end = grid.name.find('\0');
            if (end == std::string::npos)
                throwFileError(file, "NanoVDB grid " + std::to_string(grids.size() + 1) + "'s name at byte " +
                                         std::to_string(at) + " does not end with a '\\0'");
            grid.name.resize(end);
            at += nameSize;
            grids.push_back(std::move(grid));
        }
        for (size_t g = first; g < grids.size(); ++g) {
            GridEntry& grid = grids[g];
            if (grid.fileSize > size - at)
                throwFileError(file, "truncated NanoVDB file: grid " + quotedName(grid.name) + " takes " +
                                         std::to_string(grid.fileSize) + " bytes from byte " +
                                         std::to_string(at) + ", past the file's " + std::to_string(size));
            if (codec == 0 && grid.fileSize != grid.gridSize)
                throwFileError(file, "NanoVDB grid " + quotedName(grid.name) +
                                         " is uncompressed, yet takes " + std::to_string(grid.fileSize) +
                                         " bytes in the file and " + std::to_string(grid.gridSize) +
                                         " in memory");
            grid.offset = at;
            at += grid.fileSize;
        }
    }
    return grids;
}

const GridEntry& chooseGrid(const std::vector<GridEntry>& grids, const std::string& file,
                            const std::string& gridName) {
    for (const GridEntry& grid : grids) {
        if (grid.name != gridName) continue;
        if (grid.codec != 0)
            throwFileError(file,
                           "NanoVDB grid " + quotedName(gridName) + " is compressed with " +
                               (grid.codec == 1 ? "ZIP" : "BLOSC") +
                               "; penumbra reads only uncompressed NanoVDB files (codec NONE): write it "
                               "again without compression (nanovdb_convert without -z or -b)");
        if (grid.type != kTypeFloat)
            throwFileError(file, "NanoVDB grid " + quotedName(gridName) + " holds values of type " +
                                     typeName(grid.type) + "; penumbra reads grids of type float");
        return grid;
    }
    std::string names;
    for (size_t g = 0; g < grids.size() && g < 16; ++g)
        names += (g ? ", " : "") + quotedName(grids[g].name) + " (" + typeName(grids[g].type) + ")";
    if (grids.size() > 16) names += " and " + std::to_string(grids.size() - 16) + " more";
    throwFileError(file, "has no NanoVDB grid named " + quotedName(gridName) + "; its grids: " + names);
}

// One grid's buffer, every read checked against its size.
class GridBuffer {
public:
    GridBuffer(std::span<const std::byte> bytes, const std::string& file, const std::string& gridName)
        : bytes_(bytes), file_(file), gridName_(gridName) {}

    uint64_t size() const { return bytes_.size(); }
    void limitTo(uint64_t size) { bytes_ = bytes_.first(size); }

    template <typename T>
    T get(uint64_t offset) const {
        if (offset > bytes_.size() || sizeof(T) > bytes_.size() - offset)
            fail("reads " + std::to_string(sizeof(T)) + " bytes at byte " + std::to_string(offset) +
                 ", past the grid's " + std::to_string(bytes_.size()));
        T value;
        std::memcpy(&value, bytes_.data() + offset, sizeof value);
        return value;
    }

    [[noreturn]] void fail(const std::string& what) const {
        throwFileError(file_, "malformed NanoVDB grid " + quotedName(gridName_) + ": " + what);
    }

private:
    std::span<const std::byte> bytes_;
    const std::string& file_;
    const std::string& gridName_;
};

// The tree of a float grid, its nodes found from the root and each reached at most once (so that
// the work is bounded by the nodes the buffer holds): visits each active voxel of its leaves and
// each active tile of its nodes.
class Tree {
public:
    explicit Tree(const GridBuffer& buffer) : buffer_(buffer) {
        const uint64_t tree = kGridBytes, size = buffer.size();
        for (int level = 0; level < 3; ++level) {
            const auto offset = buffer.get<uint64_t>(tree + kTreeNodeOffsets + 8 * uint64_t(level));
            count_[level] = buffer.get<uint32_t>(tree + kTreeNodeCounts + 4 * uint64_t(level));
            if (count_[level] == 0) continue;
            first_[level] = tree + offset;
            if (offset > size - tree || uint64_t(count_[level]) > (size - first_[level]) / kNodeBytes[level])
                buffer.fail("its " + std::to_string(count_[level]) + " " + kNodeNames[level] +
                            "s from byte " + std::to_string(uint64_t(tree) + offset) + " end past its " +
                            std::to_string(size) + " bytes");
        }
        const auto rootOffset = buffer.get<uint64_t>(tree + kTreeNodeOffsets + 24);
        if (rootOffset > size - tree || size - tree - rootOffset < kRootBytes)
            buffer.fail("its root node at byte " + std::to_string(uint64_t(tree) + rootOffset) +
                        " ends past its " + std::to_string(size) + " bytes");
        root_ = tree + rootOffset;
        tiles_ = buffer.get<uint32_t>(root_ + kRootTableSize);
        if (tiles_ > (size - root_ - kRootBytes) / kTileBytes)
            buffer.fail("its root node's " + std::to_string(tiles_) + " tiles end past its " +
                        std::to_string(size) + " bytes");
        background_ = buffer.get<float>(root_ + kRootBackground);
        // Two root tiles at one place: NanoVDB would find only the first; the second is no part of
        // the grid, and is refused rather than guessed at.
        std::vector<std::array<int32_t, 3>> origins(tiles_);
        for (uint32_t t = 0; t < tiles_; ++t) origins[t] = tileOrigin(t);
        std::sort(origins.begin(), origins.end());
        if (std::adjacent_find(origins.begin(), origins.end()) != origins.end())
            buffer.fail("two of its root node's tiles are at the same place");
    }

    float background() const { return background_; }

    // tile(x, y, z, size, value): an active tile of size^3 voxels from (x, y, z); voxel(x, y, z,
    // value): an active voxel of a leaf.
    template <typename Tile, typename Voxel>
    void visit(Tile&& tile, Voxel&& voxel) {
        for (int level = 0; level < 3; ++level) reached_[level].assign(count_[level], false);
        for (uint32_t t = 0; t < tiles_; ++t) {
            const uint64_t at = root_ + kRootBytes + uint64_t(t) * kTileBytes;
            const auto origin = tileOrigin(t);
            const auto child = buffer_.get<int64_t>(at + kTileChild);
            if (child != 0)
                visitInternal(kUpper, node(2, root_, child), origin[0], origin[1], origin[2], tile, voxel);
            else if (buffer_.get<uint32_t>(at + kTileState) != 0)
                tile(origin[0], origin[1], origin[2], int64_t(4096), buffer_.get<float>(at + kTileValue));
        }
    }

private:
    std::array<int32_t, 3> tileOrigin(uint32_t t) const {
        const auto key = buffer_.get<uint64_t>(root_ + kRootBytes + uint64_t(t) * kTileBytes + kTileKey);
        // As NanoVDB's RootData::KeyToCoord: each 21-bit field shifted by 12, kept to 32 bits.
        auto coordinate = [&](int shift) {
            return int32_t(uint32_t(((key >> shift) & ((1u << 21) - 1)) << 12));
        };
        return {coordinate(42), coordinate(21), coordinate(0)};
    }

    // The node of `level` that `offset` from `from` points to: within the level's array, at a node's
    // start, and not reached before.
    uint64_t node(int level, uint64_t from, int64_t offset) {
        const uint64_t size = buffer_.size();
        const bool inside =
            offset >= 0 ? uint64_t(offset) < size - from : uint64_t(0) - uint64_t(offset) <= from;
        const uint64_t at = from + uint64_t(offset);
        if (!inside || count_[level] == 0 || at < first_[level] ||
            (at - first_[level]) % kNodeBytes[level] != 0 ||
            (at - first_[level]) / kNodeBytes[level] >= count_[level])
            buffer_.fail("a child offset (" + std::to_string(offset) + " from byte " + std::to_string(from) +
                         ") is not one of its " + std::to_string(count_[level]) + " " + kNodeNames[level] +
                         "s");
        const uint64_t index = (at - first_[level]) / kNodeBytes[level];
        if (reached_[level][index])
            buffer_.fail(std::string("its ") + kNodeNames[level] + " " + std::to_string(index) +
                         " is the child of two nodes");
        reached_[level][index] = true;
        return at;
    }

    template <typename Tile, typename Voxel>
    void visitInternal(const InternalLayout& layout, uint64_t at, int64_t x0, int64_t y0, int64_t z0,
                       Tile& tile, Voxel& voxel) {
        const uint32_t entries = 1u << (3 * layout.log2Dim), side = 1u << layout.log2Dim;
        for (uint32_t word = 0; word < entries / 64; ++word) {
            const auto children = buffer_.get<uint64_t>(at + layout.childMask + 8 * uint64_t(word));
            const auto active = buffer_.get<uint64_t>(at + layout.valueMask + 8 * uint64_t(word)) & ~children;
            for (uint64_t bits = children | active; bits != 0; bits &= bits - 1) {
                const uint32_t n = word * 64 + uint32_t(__builtin_ctzll(bits));
                const int64_t x = x0 + (int64_t(n >> (2 * layout.log2Dim)) << layout.childLog2);
                const int64_t y = y0 + (int64_t((n >> layout.log2Dim) & (side - 1)) << layout.childLog2);
                const int64_t z = z0 + (int64_t(n & (side - 1)) << layout.childLog2);
                const uint64_t entry = at + layout.table + 8 * uint64_t(n);
                if (children >> (n & 63) & 1) {
                    const auto offset = buffer_.get<int64_t>(entry);
                    if (&layout == &kUpper)
                        visitInternal(kLower, node(1, at, offset), x, y, z, tile, voxel);
                    else
                        visitLeaf(node(0, at, offset), x, y, z, voxel);
                } else {
                    tile(x, y, z, int64_t(1) << layout.childLog2, buffer_.get<float>(entry));
                }
            }
        }
    }

    template <typename Voxel>
    void visitLeaf(uint64_t at, int64_t x0, int64_t y0, int64_t z0, Voxel& voxel) {
        for (uint32_t word = 0; word < 8; ++word)
            for (auto bits = buffer_.get<uint64_t>(at + kLeafValueMask + 8 * uint64_t(word)); bits != 0;
                 bits &= bits - 1) {
                const uint32_t n = word * 64 + uint32_t(__builtin_ctzll(bits));
                voxel(x0 + (n >> 6), y0 + ((n >> 3) & 7), z0 + (n & 7),
                      buffer_.get<float>(at + kLeafValues + 4 * uint64_t(n)));
            }
    }

    const GridBuffer& buffer_;
    uint64_t root_ = 0, first_[3] = {0, 0, 0};
    uint32_t tiles_ = 0, count_[3] = {0, 0, 0};
    float background_ = 0;
    std::vector<bool> reached_[3];
};

DensityGrid readFloatGrid(std::span<const std::byte> bytes, const std::string& file,
                          const std::string& gridName) {
    GridBuffer buffer(bytes, file, gridName);
    if (buffer.size() < kGridBytes + kTreeBytes)
        buffer.fail("it is " + std::to_string(buffer.size()) +
                    " bytes, fewer than the 736 of its grid and tree data");
    if (buffer.get<uint64_t>(kGridMagic) != kMagic)
        buffer.fail("its grid data does not start with the magic number \"NanoVDB0\"");
    const auto version = buffer.get<uint32_t>(kGridVersion);
    if (!versionRead(version))
        buffer.fail("its grid data is of NanoVDB " + describeVersion(version) +
                    "; penumbra reads 32.3 and 32.4");
    const auto type = buffer.get<uint32_t>(kGridType);
    if (type != kTypeFloat)
        buffer.fail(std::string("its grid data says its values are of type ") + typeName(type) +
                    ", its meta data float");
    const auto gridSize = buffer.get<uint64_t>(kGridSize);
    if (gridSize < kGridBytes + kTreeBytes || gridSize > buffer.size())
        buffer.fail("its grid data gives its size as " + std::to_string(gridSize) + " bytes, the file " +
                    std::to_string(buffer.size()));
    buffer.limitTo(gridSize);

    double linear[3][3], translation[3];
    for (int r = 0; r < 3; ++r) {
        translation[r] = buffer.get<double>(kGridTranslation + 8 * uint64_t(r));
        for (int c = 0; c < 3; ++c) linear[r][c] = buffer.get<double>(kGridMatrix + 8 * uint64_t(3 * r + c));
    }
    const AxisAlignedMap map = axisAlignedMap(file, gridName, linear, translation);

    Tree tree(buffer);
    VoxelBox box;
    auto check = [&](int64_t x, int64_t y, int64_t z, float value) {
        if (!std::isfinite(value)) throwNonFiniteVoxel(file, gridName, value, x, y, z);
    };
    tree.visit(
        [&](int64_t x, int64_t y, int64_t z, int64_t size, float value) {
            check(x, y, z, value);
            box.add(x, y, z, size);
        },
        [&](int64_t x, int64_t y, int64_t z, float value) {
            check(x, y, z, value);
            box.add(x, y, z, 1);
        });
    if (box.empty()) throwFileError(file, "NanoVDB grid " + quotedName(gridName) + " has no active voxels");

    DensityGrid grid = makeLattice(file, gridName, box, map, tree.background());
    // The nodes reached are distinct, so are the voxels they cover: at most the lattice's voxels are
    // written.
    tree.visit(
        [&](int64_t x0, int64_t y0, int64_t z0, int64_t size, float value) {
            for (int64_t z = z0; z < z0 + size; ++z)
                for (int64_t y = y0; y < y0 + size; ++y) {
                    const size_t row = latticeIndex(grid, box, x0, y, z);
                    std::fill(grid.values.begin() + ptrdiff_t(row),
                              grid.values.begin() + ptrdiff_t(row + size), value);
                }
        },
        [&](int64_t x, int64_t y, int64_t z, float value) {
            grid.values[latticeIndex(grid, box, x, y, z)] = value;
        });
    return grid;
}

}  // namespace

DensityGrid readNanoVdbGridBytes(std::span<const std::byte> bytes, const std::string& fileForMessages,
                                 const std::string& gridName) {
    const ReadAt readAt = [&](uint64_t offset, void* out, size_t n) {
        std::memcpy(out, bytes.data() + offset, n);
    };
    const std::vector<GridEntry> grids = readDirectory(bytes.size(), readAt, fileForMessages);
    const GridEntry& grid = chooseGrid(grids, fileForMessages, gridName);
    return readFloatGrid(bytes.subspan(grid.offset, grid.gridSize), fileForMessages, gridName);
}

namespace {

// Reads from an open file at an offset, all of the bytes asked for.
ReadAt fileReader(const InputFile& in, const std::string& file) {
    return [&in, file](uint64_t offset, void* out, size_t n) {
        size_t done = 0;
        while (done < n) {
            const ssize_t got =
                ::pread(in.fd(), static_cast<char*>(out) + done, n - done, off_t(offset + done));
            if (got < 0 && errno == EINTR) continue;
            if (got < 0)
                throwFileError(file, std::string("cannot read the NanoVDB file: ") + std::strerror(errno));
            if (got == 0) throwFileError(file, "the NanoVDB file shrank while it was read");
            done += size_t(got);
        }
    };
}

}  // namespace

std::vector<std::string> readNanoVdbGridNames(const std::filesystem::path& path) {
    InputFile in(path, "NanoVDB file", limits::kMaxVolumeFileBytes);
    std::vector<std::string> names;
    for (const GridEntry& grid : readDirectory(in.size(), fileReader(in, path.string()), path.string()))
        names.push_back(grid.name);
    return names;
}

DensityGrid readNanoVdbGrid(const std::filesystem::path& path, const std::string& gridName) {
    InputFile in(path, "NanoVDB file", limits::kMaxVolumeFileBytes);
    const std::string file = path.string();
    const ReadAt readAt = fileReader(in, file);
    const std::vector<GridEntry> grids = readDirectory(in.size(), readAt, file);
    const GridEntry& grid = chooseGrid(grids, file, gridName);
    // Only the chosen grid's bytes are held (within the file's size, so within the limit).
    std::vector<std::byte> bytes(grid.gridSize);
    readAt(grid.offset, bytes.data(), bytes.size());
    return readFloatGrid(bytes, file, gridName);
}

}  // namespace penumbra
