// NanoVDB files written by the NanoVDB library itself (32.3.3, pbrt-v4's; tests/data/nanovdb/
// README.md says how), read by readNanoVdbGrid. The expected values are the generator's formulas,
// and the broken files are the good ones with bytes changed at places the format's documented
// layout gives (NanoVDB.h, util/IO.h), found here independently of the reader.
#include "media/nanovdb_grid.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "media/openvdb_grid.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

const std::string kData = std::string(PENUMBRA_TEST_DATA_DIR) + "/nanovdb/";
const std::string kSmoke = kData + "smoke.nvdb";

// The generator's density (make_fixtures.cpp): at voxel (i, j, k) of the box [-20, -5] x [-12, -1] x
// [-9, -2] but (-10, -6, -5); 7 over the tile [-40, -33] x [-8, -1] x [-8, -1]; voxel size 0.5,
// translated by (1, -2, 3).
float density(int i, int j, int k) {
    return 1.0f + 0.25f * float(i + 64) + 16.0f * float(j + 64) + 1024.0f * float(k + 64);
}
Vec3f densityWorld(int i, int j, int k) { return Vec3f(1.0f + 0.5f * i, -2.0f + 0.5f * j, 3.0f + 0.5f * k); }

std::vector<std::byte> readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

template <typename T>
T get(const std::vector<std::byte>& bytes, size_t offset) {
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof value);
    return value;
}
template <typename T>
void put(std::vector<std::byte>& bytes, size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof value);
}

// Where grid `index`'s buffer starts in a one-segment file: after the 16-byte header, each grid's
// 176 bytes of meta data and its name (its size at byte 136 of the meta data), then the buffers of
// the grids before it (their sizes on disk at byte 8).
size_t gridOffset(const std::vector<std::byte>& file, int index) {
    const int count = get<uint16_t>(file, 12);
    size_t at = 16, buffers = 0;
    for (int g = 0; g < count; ++g) {
        if (g < index) buffers += size_t(get<uint64_t>(file, at + 8));
        at += 176 + get<uint32_t>(file, at + 136);
    }
    return at + buffers;
}

// The density grid's structures: its TreeData (672 bytes into the grid), root node, and first
// nodes of each level.
struct DensityLayout {
    size_t grid, tree, root, firstLeaf, firstLower, firstUpper;
    explicit DensityLayout(const std::vector<std::byte>& file) {
        grid = gridOffset(file, 0);
        tree = grid + 672;
        firstLeaf = tree + size_t(get<uint64_t>(file, tree));
        firstLower = tree + size_t(get<uint64_t>(file, tree + 8));
        firstUpper = tree + size_t(get<uint64_t>(file, tree + 16));
        root = tree + size_t(get<uint64_t>(file, tree + 24));
    }
};

class ScratchFolder {
public:
    ScratchFolder() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/penumbra-nanovdb.XXXXXX";
        if (!mkdtemp(pattern.data())) ADD_FAILURE() << "mkdtemp failed";
        folder_ = pattern;
    }
    ~ScratchFolder() { std::filesystem::remove_all(folder_); }
    std::string write(const std::string& name, const std::vector<std::byte>& bytes) const {
        const std::string path = (folder_ / name).string();
        std::ofstream(path, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        return path;
    }
    const std::filesystem::path& path() const { return folder_; }

private:
    std::filesystem::path folder_;
};

// A broken file is refused, from a path (the message names it) and from bytes.
std::string expectRefused(const std::vector<std::byte>& bytes, const std::string& grid = "density") {
    ScratchFolder scratch;
    const std::string path = scratch.write("broken.nvdb", bytes);
    const InputError error = catchInputError([&] { readNanoVdbGrid(path, grid); });
    EXPECT_EQ(error.where().file, path);
    EXPECT_CONTAINS(error.what(), path);
    const InputError fromBytes = catchInputError([&] { readNanoVdbGridBytes(bytes, "bytes.nvdb", grid); });
    EXPECT_CONTAINS(fromBytes.what(), "bytes.nvdb");
    EXPECT_EQ(error.message(), fromBytes.message());
    return error.message();
}

TEST(NanoVdbGrid, DensityValuesAtVoxelsAndTilesAndBounds) {
    const DensityGrid grid = readNanoVdbGrid(kSmoke, "density");
    // Active voxels and the tile span [-40, -5] x [-12, -1] x [-9, -1].
    ASSERT_EQ(grid.nx, 36);
    ASSERT_EQ(grid.ny, 12);
    ASSERT_EQ(grid.nz, 9);
    ASSERT_EQ(grid.values.size(), size_t(36 * 12 * 9));
    // Cells of 0.5 centred on the voxels: from index -40.5 to -4.5 and so on, scaled and translated.
    EXPECT_FLOAT_EQ(grid.bounds.lower.x, 1.0f + 0.5f * -40.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.y, -2.0f + 0.5f * -12.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.z, 3.0f + 0.5f * -9.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.x, 1.0f + 0.5f * -4.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.y, -2.0f + 0.5f * -0.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.z, 3.0f + 0.5f * -0.5f);
    int checked = 0;
    for (int k = -9; k <= -1; ++k)
        for (int j = -12; j <= -1; ++j)
            for (int i = -40; i <= -5; ++i) {
                const bool inBox = i >= -20 && j <= -1 && k <= -2 && !(i == -10 && j == -6 && k == -5);
                const bool inTile = i <= -33 && j >= -8 && k >= -8;
                const float expected = inBox ? density(i, j, k) : inTile ? 7.0f : 0.0f;
                ASSERT_EQ(grid.at(i + 40, j + 12, k + 9), expected) << i << " " << j << " " << k;
                // In world space, at the voxel's centre: the voxel's value (up to the rounding of
                // the lookup's position, far below the 0.25 between neighbours in x).
                ASSERT_NEAR(grid.lookup(densityWorld(i, j, k)), expected, 0.01f) << i << " " << j << " " << k;
                ++checked;
            }
    EXPECT_EQ(checked, 36 * 12 * 9);
    // Beyond the lattice: 0.
    EXPECT_EQ(grid.lookup(densityWorld(-42, -6, -5)), 0.0f);
}

TEST(NanoVdbGrid, ChoosesTheGridByName) {
    const DensityGrid grid = readNanoVdbGrid(kSmoke, "temperature");
    ASSERT_EQ(grid.nx, 3);
    ASSERT_EQ(grid.ny, 2);
    ASSERT_EQ(grid.nz, 2);
    EXPECT_FLOAT_EQ(grid.bounds.lower.x, 0.25f * 99.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.y, 0.25f * 199.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.z, 0.25f * 299.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.x, 0.25f * 102.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.y, 0.25f * 201.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.z, 0.25f * 301.5f);
    for (int i = 100; i <= 102; ++i)
        for (int j = 200; j <= 201; ++j)
            for (int k = 300; k <= 301; ++k) {
                const float expected =
                    1000.0f + float(i - 100) + 10.0f * float(j - 200) + 100.0f * float(k - 300);
                EXPECT_EQ(grid.at(i - 100, j - 200, k - 300), expected);
                EXPECT_NEAR(grid.lookup(Vec3f(0.25f * i, 0.25f * j, 0.25f * k)), expected, 0.01f);
            }
}

TEST(NanoVdbGrid, BytesReadAsTheFile) {
    const DensityGrid fromFile = readNanoVdbGrid(kSmoke, "density");
    const DensityGrid fromBytes = readNanoVdbGridBytes(readBytes(kSmoke), "smoke", "density");
    EXPECT_EQ(fromBytes.values, fromFile.values);
    EXPECT_EQ(fromBytes.bounds.lower, fromFile.bounds.lower);
    EXPECT_EQ(fromBytes.bounds.upper, fromFile.bounds.upper);
}

// smoke.vdb holds the grids smoke.nvdb was converted from (by NanoVDB's openToNanoVDB).
TEST(NanoVdbGrid, AgreesVoxelForVoxelWithTheOpenVdbFileItWasConvertedFrom) {
    for (const char* name : {"density", "temperature"}) {
        SCOPED_TRACE(name);
        const DensityGrid nano = readNanoVdbGrid(kSmoke, name);
        const DensityGrid open = readOpenVdbGrid(kData + "smoke.vdb", name);
        ASSERT_EQ(nano.nx, open.nx);
        ASSERT_EQ(nano.ny, open.ny);
        ASSERT_EQ(nano.nz, open.nz);
        EXPECT_EQ(nano.bounds.lower, open.bounds.lower);
        EXPECT_EQ(nano.bounds.upper, open.bounds.upper);
        EXPECT_EQ(nano.values, open.values);
    }
}

TEST(NanoVdbGrid, MissingGridNamesTheFileAndItsGrids) {
    const InputError error = catchInputError([&] { readNanoVdbGrid(kSmoke, "smoke"); });
    EXPECT_EQ(error.where().file, kSmoke);
    EXPECT_CONTAINS(error.what(), "\"smoke\"");
    EXPECT_CONTAINS(error.what(), "\"density\" (float)");
    EXPECT_CONTAINS(error.what(), "\"temperature\" (float)");
    EXPECT_CONTAINS(error.what(), "\"heat\" (double)");
}

TEST(NanoVdbGrid, OtherTypesThanFloatAreRefusedByName) {
    const InputError error = catchInputError([&] { readNanoVdbGrid(kSmoke, "heat"); });
    EXPECT_EQ(error.where().file, kSmoke);
    EXPECT_CONTAINS(error.what(), "type double");
}

TEST(NanoVdbGrid, ZipCompressedFilesAreRefusedSayingSo) {
    const std::string zip = kData + "density_zip.nvdb";
    const std::vector<std::byte> bytes = readBytes(zip);
    ASSERT_EQ(get<uint16_t>(bytes, 14), 1);  // the header's codec: ZIP
    const InputError error = catchInputError([&] { readNanoVdbGrid(zip, "density"); });
    EXPECT_EQ(error.where().file, zip);
    EXPECT_CONTAINS(error.what(), "compressed with ZIP");
    EXPECT_CONTAINS(error.what(), "uncompressed");
}

TEST(NanoVdbGrid, MissingFilesAndFoldersAreRefused) {
    ScratchFolder scratch;
    EXPECT_CONTAINS(catchInputError([&] { readNanoVdbGrid(scratch.path() / "none.nvdb", "density"); }).what(),
                    "none.nvdb");
    EXPECT_CONTAINS(catchInputError([&] { readNanoVdbGrid(scratch.path(), "density"); }).what(), "a folder");
}

TEST(NanoVdbGrid, TruncatedFilesAreRefused) {
    const std::vector<std::byte> file = readBytes(kSmoke);
    const DensityLayout layout(file);
    // Within the header, the meta data, a name, the density grid's header and tree, and the last
    // grid's buffer (every grid must lie within the file), and one byte short.
    for (size_t size :
         {size_t(0), size_t(10), size_t(16), size_t(100), size_t(16 + 176 + 3), layout.grid + 100,
          layout.grid + 700, layout.firstUpper + 1000, file.size() / 2, file.size() - 1}) {
        SCOPED_TRACE(size);
        const std::string message =
            expectRefused(std::vector<std::byte>(file.begin(), file.begin() + ptrdiff_t(size)));
        if (size > 16) {
            EXPECT_CONTAINS(message, "truncated");
        }
    }
}

TEST(NanoVdbGrid, WrongMagicNumbersAndVersionsAreRefused) {
    std::vector<std::byte> file = readBytes(kSmoke);
    {
        std::vector<std::byte> bytes = file;
        bytes[0] = std::byte{'X'};
        EXPECT_CONTAINS(expectRefused(bytes), "not a NanoVDB file");
    }
    {
        std::vector<std::byte> bytes = file;
        put<uint64_t>(bytes, 0, 0x324244566f6e614eull);  // "NanoVDB2", NanoVDB 32.6's files
        EXPECT_CONTAINS(expectRefused(bytes), "32.6 or later");
    }
    {
        std::vector<std::byte> bytes = file;
        put<uint32_t>(bytes, 8, 31u << 21 | 1u << 10);  // version 31.1.0
        EXPECT_CONTAINS(expectRefused(bytes), "31.1.0");
    }
    {
        // The grid's own magic number.
        std::vector<std::byte> bytes = file;
        put<uint64_t>(bytes, DensityLayout(file).grid, 0);
        EXPECT_CONTAINS(expectRefused(bytes), "magic number");
    }
}

TEST(NanoVdbGrid, CorruptOffsetsAndCountsAreRefused) {
    const std::vector<std::byte> file = readBytes(kSmoke);
    const DensityLayout layout(file);
    const size_t firstTileChild = layout.root + 64 + 8;
    ASSERT_NE(get<int64_t>(file, firstTileChild), 0);  // the density's one root tile has a child
    for (int64_t change : {int64_t(32), int64_t(-32), int64_t(1) << 40, -(int64_t(1) << 40),
                           std::numeric_limits<int64_t>::min() / 2}) {
        SCOPED_TRACE(change);
        std::vector<std::byte> bytes = file;
        put<int64_t>(bytes, firstTileChild, get<int64_t>(file, firstTileChild) + change);
        EXPECT_CONTAINS(expectRefused(bytes), "child offset");
    }
    {
        // The root node's offset and its table size beyond the grid.
        std::vector<std::byte> bytes = file;
        put<uint64_t>(bytes, layout.tree + 24, uint64_t(1) << 62);
        EXPECT_CONTAINS(expectRefused(bytes), "root node");
        bytes = file;
        put<uint32_t>(bytes, layout.root + 24, 0xffffffffu);
        EXPECT_CONTAINS(expectRefused(bytes), "tiles end past");
    }
    {
        // More leaves than the grid holds.
        std::vector<std::byte> bytes = file;
        put<uint32_t>(bytes, layout.tree + 32, 1u << 20);
        EXPECT_CONTAINS(expectRefused(bytes), "leaf nodes");
    }
    {
        // Two children of a lower node pointing at one leaf.
        std::vector<std::byte> bytes = file;
        const size_t childMask = layout.firstLower + 544, table = layout.firstLower + 1088;
        std::vector<uint32_t> children;
        for (uint32_t n = 0; n < 4096 && children.size() < 2; ++n)
            if (get<uint64_t>(file, childMask + 8 * (n / 64)) >> (n % 64) & 1) children.push_back(n);
        ASSERT_EQ(children.size(), 2u);
        // Offsets are from the node, so the same offset is the same leaf.
        put<int64_t>(bytes, table + 8 * children[1], get<int64_t>(file, table + 8 * children[0]));
        EXPECT_CONTAINS(expectRefused(bytes), "child of two nodes");
    }
    {
        // A grid size in the meta data beyond the file.
        std::vector<std::byte> bytes = file;
        put<uint64_t>(bytes, 16 + 8, uint64_t(1) << 50);
        put<uint64_t>(bytes, 16, uint64_t(1) << 50);
        EXPECT_CONTAINS(expectRefused(bytes), "truncated");
    }
}

TEST(NanoVdbGrid, ValuesThatAreNotFiniteAreRefused) {
    std::vector<std::byte> bytes = readBytes(kSmoke);
    const DensityLayout layout(bytes);
    for (int n = 0; n < 512; ++n) put<float>(bytes, layout.firstLeaf + 96 + 4 * size_t(n), std::nanf(""));
    EXPECT_CONTAINS(expectRefused(bytes), "not finite");
}

TEST(NanoVdbGrid, LatticesBeyondTheVoxelLimitAreRefusedBeforeAllocating) {
    // Entry 0 of the upper node made an active tile of 128^3 voxels at (-4096, -4096, -4096): the
    // active voxels then span 4092 voxels a side.
    std::vector<std::byte> bytes = readBytes(kSmoke);
    const DensityLayout layout(bytes);
    ASSERT_EQ(get<uint64_t>(bytes, layout.firstUpper + 4128) & 1, 0u);  // entry 0 has no child
    put<uint64_t>(bytes, layout.firstUpper + 32, get<uint64_t>(bytes, layout.firstUpper + 32) | 1);
    put<float>(bytes, layout.firstUpper + 8256, 1.0f);
    const std::string message = expectRefused(bytes);
    EXPECT_CONTAINS(message, "4092 x 4096 x 4096");
    EXPECT_CONTAINS(message, "at most 268435456 voxels");
}

TEST(NanoVdbGrid, RotatedTransformsAreRefused) {
    std::vector<std::byte> bytes = readBytes(kSmoke);
    const size_t matrix = DensityLayout(bytes).grid + 296 + 88;
    put<double>(bytes, matrix + 8, 0.25);  // row 0, column 1
    EXPECT_CONTAINS(expectRefused(bytes), "rotates or shears");
    bytes = readBytes(kSmoke);
    put<double>(bytes, matrix, -0.5);
    EXPECT_CONTAINS(expectRefused(bytes), "mirrors");
}

}  // namespace
}  // namespace penumbra
