// The scene file's "media" section (scenes/medium_reader.h): the keys of each type, grids inline
// and from OpenVDB and NanoVDB files (tests/data/nanovdb: both files hold the same grid, written
// by the OpenVDB and NanoVDB libraries), the shapes' and camera's media, and what is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "media/nanovdb_grid.h"
#include "media/openvdb_grid.h"
#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using testing::catchInputError;

const fs::path kVolumes = fs::path(PENUMBRA_TEST_DATA_DIR) / "nanovdb";

Scene parseIn(const fs::path& folder, const std::string& json) {
    return parseScene(json, folder / "scene.json");
}

TEST(MediumLoader, HomogeneousAndInlineGridMediaWithTheirBoundariesAndTheCamera) {
    const Scene scene = parseIn(kVolumes, R"({
        "camera": {"medium": "fog"},
        "media": {
            "fog": {"type": "homogeneous", "sigma_a": [0.1, 0.2, 0.3], "sigma_s": 0.5, "scale": 2, "g": -0.25,
                    "emission": 1.5},
            "ramp": {"type": "grid", "sigma_s": 1, "density": {"resolution": [2, 1, 1], "values": [0, 3]},
                     "bounds": [[0, 0, 0], [2, 1, 1]], "transform": [{"translate": [1, 0, 0]}]}
        },
        "materials": {"m": {"type": "interface"}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m", "inside": "ramp",
                    "outside": "fog"},
                   {"type": "sphere", "center": [5, 0, 0], "radius": 1, "material": "m", "inside": "ramp"},
                   {"type": "sphere", "center": [9, 0, 0], "radius": 1, "material": "m"}]})");
    ASSERT_EQ(scene.media.size(), 2u);
    const auto& fog = std::get<HomogeneousMedium>(scene.media[0]);
    EXPECT_FLOAT_EQ(fog.sigmaA.b, 0.6f);
    EXPECT_FLOAT_EQ(fog.sigmaS.r, 1.0f);
    EXPECT_FLOAT_EQ(fog.phase.g, -0.25f);
    EXPECT_FLOAT_EQ(fog.emission.g, 1.5f);
    const auto& ramp = std::get<GridMedium>(scene.media[1]);
    EXPECT_EQ(ramp.density.nx, 2);
    EXPECT_FLOAT_EQ(ramp.density.lookup({1.5f, 0.5f, 0.5f}), 3.0f);  // the second cell's centre
    EXPECT_FLOAT_EQ(ramp.toWorld.applyPoint({0, 0, 0}).x, 1.0f);
    EXPECT_EQ(scene.cameraMedium, 0u);
    EXPECT_EQ(scene.spheres[0].media.inside, 1u);
    EXPECT_EQ(scene.spheres[0].media.outside, 0u);
    EXPECT_EQ(scene.spheres[1].media.outside, MediumInterface::kVacuum);  // not given: the vacuum
    EXPECT_FALSE(scene.spheres[2].media.isTransition());
    EXPECT_TRUE(scene.hasMedia());
}

// A measured medium by name: Jensen et al. 2001's whole milk, sigma'_s (2.55, 3.21, 3.77) and
// sigma_a (0.0011, 0.0024, 0.014) per mm, here per 10 scene units (scale 10: scene units of 0.1 mm).
TEST(MediumLoader, PresetsAreMeasuredCoefficientsTimesTheScale) {
    const Scene scene = parseIn(
        kVolumes, R"({"media": {"milk": {"type": "homogeneous", "preset": "Wholemilk", "scale": 0.1}}})");
    const auto& milk = std::get<HomogeneousMedium>(scene.media[0]);
    EXPECT_FLOAT_EQ(milk.sigmaS.b, 0.377f);
    EXPECT_FLOAT_EQ(milk.sigmaA.r, 0.00011f);
    const InputError e = catchInputError([] {
        parseIn(kVolumes,
                R"({"media": {"m": {"type": "homogeneous", "preset": "Wholemilk", "sigma_s": 1}}})");
    });
    EXPECT_CONTAINS(e.message(), "either");
    const InputError unknown = catchInputError(
        [] { parseIn(kVolumes, R"({"media": {"m": {"type": "homogeneous", "preset": "Whole milk"}}})"); });
    EXPECT_EQ(unknown.where().jsonPointer, "/media/m/preset");
}

TEST(MediumLoader, GridsFromOpenVdbAndNanoVdbFilesAgree) {
    const Scene scene = parseIn(kVolumes, R"({"media": {
        "a": {"type": "grid", "sigma_s": 1, "density": {"file": "smoke.vdb"}},
        "b": {"type": "grid", "density": {"file": "smoke.nvdb", "grid": "density"}}}})");
    const DensityGrid& a = std::get<GridMedium>(scene.media[0]).density;
    const DensityGrid& b = std::get<GridMedium>(scene.media[1]).density;
    EXPECT_EQ(a.nx, b.nx);
    EXPECT_EQ(a.ny, b.ny);
    EXPECT_EQ(a.nz, b.nz);
    EXPECT_EQ(a.values, b.values);
    EXPECT_EQ(a.bounds.lower, b.bounds.lower);
    EXPECT_EQ(a.bounds.upper, b.bounds.upper);
    // The majorants bound sigma_t = the density: the coarse cell over the whole grid's largest value.
    float largest = 0.0f;
    for (float v : a.values) largest = std::max(largest, v);
    float largestMajorant = 0.0f;
    for (Rgb m : std::get<GridMedium>(scene.media[0]).majorants.sigmaMaj)
        largestMajorant = std::max(largestMajorant, m.maxComponent());
    EXPECT_EQ(largestMajorant, largest);
}

// Emission: a temperature grid from a file (placed where the file says) with its offset and scale,
// times an emission scale; an inline emission-scale lattice spans the density's bounds; an
// rgb_grid's lattices and uniform colours; a cloud's keys; a file's float grid as the emission scale.
TEST(MediumLoader, EmittingGridsRgbGridsAndClouds) {
    const Scene scene = parseIn(kVolumes, R"({"media": {
        "fire": {"type": "grid", "sigma_a": 1, "density": {"file": "smoke.nvdb"},
                 "temperature": {"file": "smoke.nvdb", "grid": "temperature"}, "temperature_offset": 10,
                 "temperature_scale": 3, "emission_scale": 2},
        "lamp": {"type": "grid", "density": {"resolution": [1, 1, 1], "values": [1]}, "bounds": [[0, 0, 0], [4, 4, 4]],
                 "emission": [1, 2, 3], "emission_scale": {"resolution": [2, 1, 1], "values": [5, 7]}},
        "tint": {"type": "rgb_grid", "resolution": [2, 1, 1], "sigma_a": {"values": [1, 2, 3, 4, 5, 6]},
                 "sigma_s": 0.5, "emission": [1, 1, 0], "scale": 2, "bounds": [[0, 0, 0], [2, 1, 1]]},
        "puff": {"type": "cloud", "sigma_s": 4, "density": 0, "wispiness": 0, "frequency": 2,
                 "bounds": [[0, 0, 0], [1, 2, 1]]},
        "glow": {"type": "grid", "density": {"file": "smoke.vdb"}, "emission": [1, 0.5, 0.25],
                 "emission_scale": {"file": "smoke.vdb", "grid": "temperature"}}}})");
    const auto& fire = std::get<GridMedium>(scene.media[0]);
    ASSERT_TRUE(fire.emission.temperature.has_value());
    const DensityGrid temperature = readNanoVdbGrid(kVolumes / "smoke.nvdb", "temperature");
    EXPECT_EQ(fire.emission.temperature->values, temperature.values);
    EXPECT_EQ(fire.emission.temperature->bounds.lower, temperature.bounds.lower);
    EXPECT_FLOAT_EQ(fire.emission.temperatureOffset, 10.0f);
    EXPECT_FLOAT_EQ(fire.emission.temperatureScale, 3.0f);
    EXPECT_FLOAT_EQ(fire.emission.scale, 2.0f);
    const auto& lamp = std::get<GridMedium>(scene.media[1]);
    ASSERT_TRUE(lamp.emission.scaleGrid.has_value());
    EXPECT_EQ(lamp.emission.scaleGrid->bounds.upper, Vec3f(4, 4, 4));
    EXPECT_EQ(lamp.emission.at({3.0f, 2.0f, 2.0f}), Rgb(7.0f, 14.0f, 21.0f));  // the second cell's centre
    const auto& tint = std::get<RgbGridMedium>(scene.media[2]);
    EXPECT_EQ(tint.sigmaAAt({1.5f, 0.5f, 0.5f}), Rgb(8.0f, 10.0f, 12.0f));
    EXPECT_EQ(tint.sigmaSAt({1.9f, 0.1f, 0.9f}), Rgb(1.0f));  // uniform in the box, times scale
    EXPECT_EQ(tint.sigmaSAt({2.1f, 0.5f, 0.5f}), Rgb(0.0f));  // nothing outside it
    EXPECT_EQ(tint.emissionAt({0.2f, 0.5f, 0.5f}), Rgb(1.0f, 1.0f, 0.0f));
    const auto& puff = std::get<CloudMedium>(scene.media[3]);
    EXPECT_FLOAT_EQ(puff.frequency, 2.0f);
    EXPECT_EQ(puff.bounds.upper, Vec3f(1, 2, 1));
    EXPECT_FLOAT_EQ(puff.densityAt({0.5f, 0.25f, 0.5f}), 0.5f);  // density 0: the base alone, 1 - 2y
    EXPECT_EQ(puff.majorants.sigmaMaj[0], Rgb(4.0f));
    // An OpenVDB file's float grid as the emission's scale (a Houdini or Blender "emission" grid).
    const auto& glow = std::get<GridMedium>(scene.media[4]);
    ASSERT_TRUE(glow.emission.scaleGrid.has_value());
    EXPECT_EQ(glow.emission.scaleGrid->values, readOpenVdbGrid(kVolumes / "smoke.vdb", "temperature").values);
    EXPECT_EQ(glow.emission.radiance, Rgb(1.0f, 0.5f, 0.25f));
}

TEST(MediumLoader, MistakesAreRefusedAtTheirPointer) {
    struct Case {
        const char* json;
        const char* pointer;
        const char* expected;
    };
    for (
        const Case& c : {
            Case{R"({"media": {"f": {"type": "homogeneous", "sigma_a": -1}}})", "/media/f/sigma_a", ">= 0"},
            Case{R"({"media": {"f": {"type": "homogeneous", "g": 1}}})", "/media/f/g", "0.99"},
            Case{R"({"media": {"": {"type": "homogeneous"}}})", "/media/", "vacuum"},
            Case{R"({"media": {"f": {"type": "fog"}}})", "/media/f/type", "homogeneous"},
            Case{R"({"media": {"g": {"type": "grid", "density": {"resolution": [2, 2, 2], "values": [1]}}}})",
                 "/media/g/density/values", "8 numbers"},
            Case{
                R"({"media": {"g": {"type": "grid", "density": {"file": "smoke.vdb"}, "bounds": [[0, 0, 0], [1, 1, 1]]}}})",
                "/media/g/bounds", "where the file says"},
            Case{R"({"media": {"g": {"type": "grid", "density": {"file": "README.md"}}}})",
                 "/media/g/density/file", ".vdb"},
            Case{R"({"media": {"g": {"type": "grid", "density": {"file": "none.vdb"}}}})",
                 "/media/g/density/file", "does not exist"},
            Case{R"({"media": {"g": {"type": "grid", "density": {"resolution": [1, 1, 1], "values": [1]},
                  "emission": 1, "temperature": {"resolution": [1, 1, 1], "values": [1000]}}}})",
                 "/media/g/emission", "either"},
            Case{R"({"media": {"g": {"type": "grid", "density": {"resolution": [1, 1, 1], "values": [1]},
                  "temperature_scale": 2}}})",
                 "/media/g/temperature_scale", "there is none"},
            Case{
                R"({"media": {"c": {"type": "rgb_grid", "resolution": [2, 1, 1], "sigma_a": {"values": [1, 2, 3]}}}})",
                "/media/c/sigma_a/values", "6 numbers"},
            Case{R"({"media": {"c": {"type": "rgb_grid", "resolution": [2, 1, 1], "emission": 1}}})",
                 "/media/c", "sigma_a, sigma_s or both"},
            Case{R"({"camera": {"medium": "smoke"}})", "/camera/medium", "unknown medium \"smoke\""},
            Case{
                R"({"materials": {"m": {"type": "interface"}}, "shapes": [{"type": "sphere", "center": [0, 0, 0],
                  "radius": 1, "material": "m", "inside": "fog"}]})",
                "/shapes/0/inside", "the scene defines no media"},
        }) {
        const InputError e = catchInputError([&] { parseIn(kVolumes, c.json); });
        EXPECT_EQ(e.where().jsonPointer, c.pointer) << c.json;
        EXPECT_CONTAINS(e.message(), c.expected);
    }
    // A grid the file does not have: the reader's message, naming the file.
    const InputError e = catchInputError([&] {
        parseIn(kVolumes,
                R"({"media": {"g": {"type": "grid", "density": {"file": "smoke.vdb", "grid": "soot"}}}})");
    });
    EXPECT_CONTAINS(e.what(), "smoke.vdb");
}

}  // namespace
}  // namespace penumbra
