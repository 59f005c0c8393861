// The catalogue of malformed pbrt-v4 scenes (tests/data/pbrt/malformed): each file's first line
// says where the error must be reported and how it begins ("# expect: LINE:COLUMN: message");
// loading the file must throw InputError with exactly that place in the file and that message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "formats/scene_file.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

const fs::path kCatalogue = fs::path(PENUMBRA_TEST_DATA_DIR) / "pbrt" / "malformed";

TEST(PbrtMalformed, EveryFileIsAClearErrorAtItsPlace) {
    int files = 0;
    for (const auto& entry : fs::directory_iterator(kCatalogue)) {
        if (entry.path().extension() != ".pbrt") continue;
        ++files;
        std::ifstream in(entry.path());
        std::string first;
        std::getline(in, first);
        const std::string prefix = "# expect: ";
        ASSERT_EQ(first.rfind(prefix, 0), 0u) << entry.path() << " has no '# expect:' line";
        const std::string expected = entry.path().string() + ":" + first.substr(prefix.size());
        std::vector<std::string> warnings;
        try {
            loadSceneFile(entry.path(), {{}, &warnings});
            ADD_FAILURE() << entry.path().filename() << ": loaded without an error";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(expected, 0), 0u)
                << entry.path().filename() << "\n  expected: " << expected << "\n  got:      " << what;
        }
    }
    EXPECT_GE(files, 15);
}

}  // namespace
}  // namespace penumbra
