// The shared test data: scenes, meshes and reference images made by others (Bitterli's Rendering
// Resources, rendered by Tungsten and Mitsuba 3; the Stanford scanning repository's meshes),
// kept outside the repository in ../shared/data beside the checkout, whose README lists each
// file's origin and licence. Tests find it through PENUMBRA_DATA_DIR and are skipped, with
// this message, when a file is absent.
#pragma once

#include <filesystem>
#include <string>

namespace penumbra::testing {

inline std::string sharedDataMissing(const std::filesystem::path& file) {
    return "needs " + file.string() +
           " from the shared test data (reference images and meshes made by others, kept outside the "
           "repository: ../shared/data beside the checkout, whose README says where each file comes from); "
           "point to another copy with cmake -S . -B build -DPENUMBRA_DATA_DIR=FOLDER";
}

}  // namespace penumbra::testing

// Skips the current test when `file` (a path in the shared data) does not exist.
#define PENUMBRA_SKIP_WITHOUT_SHARED_DATA(file)                                                           \
    do {                                                                                                  \
        if (!std::filesystem::exists(file)) GTEST_SKIP() << ::penumbra::testing::sharedDataMissing(file); \
    } while (false)
