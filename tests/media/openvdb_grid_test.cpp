// OpenVDB files written here with the OpenVDB library, read by readOpenVdbGrid: the expected values
// are the functions the grids were filled with, at the world positions of the voxel centres under
// the transforms the test chose.
#include "media/openvdb_grid.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/math/Maps.h>
#include <openvdb/openvdb.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

class ScratchFolder {
public:
    ScratchFolder() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/penumbra-openvdb.XXXXXX";
        if (!mkdtemp(pattern.data())) ADD_FAILURE() << "mkdtemp failed";
        folder_ = pattern;
    }
    ~ScratchFolder() { std::filesystem::remove_all(folder_); }
    std::string path(const std::string& name) const { return (folder_ / name).string(); }

private:
    std::filesystem::path folder_;
};

// Voxel (i, j, k) of "density": active over [-3, 4] x [2, 6] x [-1, 1] but (0, 3, 0), plus a tile of
// 8^3 voxels of 5 at [8, 15] x [0, 7] x [0, 7]; voxel size 0.5, translated by (0.25, 4, -1).
float density(int i, int j, int k) { return 1000.0f + float(i) + 10.0f * float(j) + 100.0f * float(k); }
Vec3f densityWorld(int i, int j, int k) { return Vec3f(0.25f + 0.5f * i, 4.0f + 0.5f * j, -1.0f + 0.5f * k); }

openvdb::FloatGrid::Ptr densityGrid() {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    auto transform = openvdb::math::Transform::createLinearTransform(0.5);
    transform->postTranslate(openvdb::Vec3d(0.25, 4.0, -1.0));
    grid->setTransform(transform);
    auto access = grid->getAccessor();
    for (int i = -3; i <= 4; ++i)
        for (int j = 2; j <= 6; ++j)
            for (int k = -1; k <= 1; ++k) access.setValue(openvdb::Coord(i, j, k), density(i, j, k));
    access.setValueOff(openvdb::Coord(0, 3, 0), 0.0f);
    grid->tree().addTile(1, openvdb::Coord(8, 0, 0), 5.0f, true);
    return grid;
}

openvdb::FloatGrid::Ptr floatGrid(const std::string& name, openvdb::math::Transform::Ptr transform) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName(name);
    grid->setTransform(transform);
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    return grid;
}

class OpenVdbGrid : public ::testing::Test {
protected:
    static void SetUpTestSuite() { openvdb::initialize(); }

    // A file of `grids`; returns its path.
    std::string write(const std::string& name, const openvdb::GridPtrVec& grids) {
        const std::string path = scratch_.path(name);
        openvdb::io::File(path).write(grids);
        return path;
    }

    ScratchFolder scratch_;
};

TEST_F(OpenVdbGrid, ValuesAtVoxelCentresInWorldSpaceAndBounds) {
    const std::string path = write("density.vdb", {densityGrid()});
    const DensityGrid grid = readOpenVdbGrid(path, "density");
    // Active voxels and the tile: [-3, 15] x [0, 7] x [-1, 7].
    ASSERT_EQ(grid.nx, 19);
    ASSERT_EQ(grid.ny, 8);
    ASSERT_EQ(grid.nz, 9);
    EXPECT_FLOAT_EQ(grid.bounds.lower.x, 0.25f + 0.5f * -3.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.y, 4.0f + 0.5f * -0.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.z, -1.0f + 0.5f * -1.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.x, 0.25f + 0.5f * 15.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.y, 4.0f + 0.5f * 7.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.z, -1.0f + 0.5f * 7.5f);
    for (int k = -1; k <= 7; ++k)
        for (int j = 0; j <= 7; ++j)
            for (int i = -3; i <= 15; ++i) {
                const bool inBox = i <= 4 && j >= 2 && j <= 6 && k <= 1 && !(i == 0 && j == 3 && k == 0);
                const bool inTile = i >= 8 && k >= 0;
                const float expected = inBox ? density(i, j, k) : inTile ? 5.0f : 0.0f;
                // Within the rounding of the lookup's position: neighbours differ by at least 1.
                ASSERT_NEAR(grid.lookup(densityWorld(i, j, k)), expected, 0.01f) << i << " " << j << " " << k;
            }
    // Halfway between two voxels in x: their mean.
    EXPECT_NEAR(grid.lookup(densityWorld(1, 4, 1) + Vec3f(0.25f, 0, 0)),
                0.5f * (density(1, 4, 1) + density(2, 4, 1)), 0.01f);
}

TEST_F(OpenVdbGrid, NonUniformScaleAndTheGridByName) {
    auto scaled =
        floatGrid("temperature", openvdb::math::Transform::Ptr(new openvdb::math::Transform(
                                     openvdb::math::MapBase::Ptr(new openvdb::math::ScaleTranslateMap(
                                         openvdb::Vec3d(0.5, 1.0, 2.0), openvdb::Vec3d(1.0, 2.0, 3.0))))));
    scaled->tree().setValue(openvdb::Coord(2, 2, 3), 3.0f);
    const std::string path = write("two.vdb", {densityGrid(), scaled});
    const DensityGrid grid = readOpenVdbGrid(path, "temperature");
    ASSERT_EQ(grid.nx, 2);
    ASSERT_EQ(grid.ny, 1);
    ASSERT_EQ(grid.nz, 1);
    EXPECT_FLOAT_EQ(grid.bounds.lower.x, 1.0f + 0.5f * 0.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.x, 1.0f + 0.5f * 2.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.y, 2.0f + 1.0f * 1.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.y, 2.0f + 1.0f * 2.5f);
    EXPECT_FLOAT_EQ(grid.bounds.lower.z, 3.0f + 2.0f * 2.5f);
    EXPECT_FLOAT_EQ(grid.bounds.upper.z, 3.0f + 2.0f * 3.5f);
    EXPECT_NEAR(grid.lookup(Vec3f(1.5f, 4.0f, 9.0f)), 1.0f, 1e-5f);
    EXPECT_NEAR(grid.lookup(Vec3f(2.0f, 4.0f, 9.0f)), 3.0f, 1e-5f);
}

TEST_F(OpenVdbGrid, MissingGridNamesTheFileAndItsGrids) {
    auto velocity = openvdb::Vec3SGrid::create();
    velocity->setName("vel");
    const std::string path = write("smoke.vdb", {densityGrid(), velocity});
    const InputError error = catchInputError([&] { readOpenVdbGrid(path, "temperature"); });
    EXPECT_EQ(error.where().file, path);
    EXPECT_CONTAINS(error.what(), "\"temperature\"");
    EXPECT_CONTAINS(error.what(), "\"density\" (float)");
    EXPECT_CONTAINS(error.what(), "\"vel\" (vec3s)");
}

TEST_F(OpenVdbGrid, OtherTypesThanFloatAreRefused) {
    auto velocity = openvdb::Vec3SGrid::create();
    velocity->setName("vel");
    auto heat = openvdb::DoubleGrid::create();
    heat->setName("heat");
    const std::string path = write("types.vdb", {velocity, heat});
    for (const auto& [name, type] : {std::pair{"vel", "vec3s"}, std::pair{"heat", "double"}}) {
        const InputError error = catchInputError([&] { readOpenVdbGrid(path, name); });
        EXPECT_EQ(error.where().file, path);
        EXPECT_CONTAINS(error.what(), std::string("type ") + type);
    }
}

TEST_F(OpenVdbGrid, RotatedAndFrustumTransformsAreRefused) {
    auto rotation = openvdb::math::Transform::createLinearTransform(0.5);
    rotation->postRotate(0.3, openvdb::math::Z_AXIS);
    const openvdb::BBoxd box(openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(10, 10, 10));
    auto frustum = openvdb::math::Transform::createFrustumTransform(box, 0.5, 2.0, 1.0);
    auto mirror = openvdb::math::Transform::createLinearTransform(0.5);
    mirror->postScale(openvdb::Vec3d(1.0, -1.0, 1.0));
    const std::string path =
        write("transforms.vdb",
              {floatGrid("rotated", rotation), floatGrid("frustum", frustum), floatGrid("mirrored", mirror)});
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(path, "rotated"); }).what(), "rotates or shears");
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(path, "frustum"); }).what(), "not linear");
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(path, "mirrored"); }).what(), "mirrors");
}

TEST_F(OpenVdbGrid, EmptyHugeAndNotFiniteGridsAreRefused) {
    auto empty = openvdb::FloatGrid::create(0.0f);
    empty->setName("empty");
    auto huge = floatGrid("huge", openvdb::math::Transform::createLinearTransform(1.0));
    huge->tree().setValue(openvdb::Coord(100000, 100000, 0), 1.0f);
    auto nan = floatGrid("nan", openvdb::math::Transform::createLinearTransform(1.0));
    nan->tree().setValue(openvdb::Coord(4, 5, 6), std::nanf(""));
    const std::string path = write("bad.vdb", {empty, huge, nan});
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(path, "empty"); }).what(), "no active voxels");
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(path, "huge"); }).what(),
                    "at most 268435456 voxels");
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(path, "nan"); }).what(), "(4, 5, 6)");
}

TEST_F(OpenVdbGrid, FilesThatAreNotOpenVdbAreRefused) {
    const std::string text = scratch_.path("text.vdb");
    std::ofstream(text) << "not a VDB file\n";
    const InputError error = catchInputError([&] { readOpenVdbGrid(text, "density"); });
    EXPECT_EQ(error.where().file, text);
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(scratch_.path("none.vdb"), "density"); }).what(),
                    "none.vdb");
    EXPECT_CONTAINS(catchInputError([&] { readOpenVdbGrid(scratch_.path(""), "density"); }).what(),
                    "a folder");
}

}  // namespace
}  // namespace penumbra
