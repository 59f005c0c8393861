// `penumbra render --accel embree|bvh`: the backend is chosen and recorded in the EXR's metadata.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/support/run_command.h"

namespace {

namespace fs = std::filesystem;

using penumbra::testing::runPenumbra;

TEST(AccelOption, TheChosenBackendRendersAndIsRecorded) {
    const fs::path dir = fs::temp_directory_path() / "penumbra-accel-option";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box.json";
    for (const std::string accel : {"embree", "bvh"}) {
        const fs::path exr = dir / (accel + ".exr");
        const auto run = runPenumbra("render " + scene + " --accel " + accel +
                                     " --res 16x16 --spp 2 --no-display -q -o " + exr.string());
        ASSERT_EQ(run.exitCode, 0) << run.output;
        auto in = OIIO::ImageInput::open(exr.string());
        ASSERT_TRUE(in) << exr;
        EXPECT_EQ(in->spec().get_string_attribute("penumbra:accel"), accel);
    }
    const auto refused = runPenumbra("render " + scene + " --accel optix -o " + (dir / "x.exr").string());
    EXPECT_NE(refused.exitCode, 0);
    EXPECT_NE(refused.output.find("--accel"), std::string::npos) << refused.output;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    fs::remove_all(dir);
}

}  // namespace
