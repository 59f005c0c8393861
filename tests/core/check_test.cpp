// PENUMBRA_CHECK: with the checks on (Debug, or PENUMBRA_CHECKS=ON) a false condition aborts with
// its place and meaning; with them off it compiles to nothing, not even the condition.
#include "core/check.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

#ifdef NDEBUG
TEST(InvariantCheck, CompiledOutInReleaseBuilds) {
    int evaluated = 0;
    PENUMBRA_CHECK(++evaluated > 0, "never evaluated");
    EXPECT_EQ(evaluated, 0);
}
#else
TEST(InvariantCheckDeathTest, FalseConditionAbortsWithItsMeaning) {
    int evaluated = 0;
    PENUMBRA_CHECK(++evaluated > 0, "holds");
    EXPECT_EQ(evaluated, 1);
    EXPECT_DEATH(PENUMBRA_CHECK(evaluated < 0, "a count is negative"),
                 "invariant violated at .*check_test.cpp:[0-9]+: a count is negative");
}
#endif

}  // namespace
}  // namespace penumbra
