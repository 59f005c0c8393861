// `penumbra render --accel embree|bvh`: the backend is chosen and recorded in the EXR's metadata.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <OpenImageIO/imageio.h>

namespace {

namespace fs = std::filesystem;

int runPenumbra(const std::string& arguments, std::string& output) {
    FILE* pipe = popen((std::string(PENUMBRA_BINARY) + " " + arguments + " 2>&1").c_str(), "r");
    if (!pipe) return -1;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output.append(buffer.data(), n);
    const int status = pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(AccelOption, TheChosenBackendRendersAndIsRecorded) {
    const fs::path dir = fs::temp_directory_path() / "penumbra-accel-option";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box.json";
    for (const std::string accel : {"embree", "bvh"}) {
        const fs::path exr = dir / (accel + ".exr");
        std::string output;
        ASSERT_EQ(runPenumbra("render " + scene + " --accel " + accel +
                                  " --res 16x16 --spp 2 --no-display -q -o " + exr.string(),
                              output),
                  0)
            << output;
        auto in = OIIO::ImageInput::open(exr.string());
        ASSERT_TRUE(in) << exr;
        EXPECT_EQ(in->spec().get_string_attribute("penumbra:accel"), accel);
    }
    std::string output;
    EXPECT_NE(runPenumbra("render " + scene + " --accel optix -o " + (dir / "x.exr").string(), output), 0);
    EXPECT_NE(output.find("--accel"), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    fs::remove_all(dir);
}

}  // namespace
