// Declared sizes are checked against the memory available now (MemAvailable), not the machine's
// total: 19.3 GiB (what the sums of a 9000x9000 film once took) fit in 32 GiB but not in the 16
// GiB left free.
#include "core/system_memory.h"

#include <gtest/gtest.h>

#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

constexpr double kGiB = 0x1p30;
const double kFilm9000 = 9000.0 * 9000.0 * 256.0;  // 256 bytes a pixel

TEST(SystemMemory, RefusesWhatExceedsTheAvailableMemoryThoughNotTheTotal) {
    const SystemMemory memory{uint64_t(16 * kGiB), uint64_t(32 * kGiB)};
    const InputError e = catchInputError([&] { requireMemory(kFilm9000, "a 9000x9000 film", memory); });
    EXPECT_CONTAINS(
        e.what(),
        "a 9000x9000 film needs 19.3 GiB of memory; this machine has 16.0 GiB available (of 32.0 GiB)");
}

TEST(SystemMemory, AcceptsWhatFits) {
    EXPECT_NO_THROW(
        requireMemory(kFilm9000, "a film", SystemMemory{uint64_t(24 * kGiB), uint64_t(32 * kGiB)}));
}

TEST(SystemMemory, FallsBackToTheTotalWhenTheAvailableMemoryIsUnknown) {
    const InputError e = catchInputError([&] {
        requireMemory(kFilm9000, "a film", SystemMemory{0, uint64_t(8 * kGiB)});
    });
    EXPECT_CONTAINS(e.what(), "a film needs 19.3 GiB of memory; this machine has 8.0 GiB");
}

TEST(SystemMemory, ReadsThisMachinesMemory) {
    const SystemMemory memory = systemMemory();
    EXPECT_GT(memory.totalBytes, 0u);
    EXPECT_LE(memory.availableBytes, memory.totalBytes);
}

}  // namespace
}  // namespace penumbra
