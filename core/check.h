// Invariant checks for Debug builds: PENUMBRA_CHECK(condition, what) aborts with the condition,
// what it means, and the place when the condition is false. Release builds (NDEBUG) compile it to
// nothing, so it may sit on the hottest paths; the condition must have no side effects.
#pragma once

namespace penumbra::detail {

[[noreturn]] void checkFailed(const char* condition, const char* what, const char* file, int line);

}  // namespace penumbra::detail

#ifdef NDEBUG
#define PENUMBRA_CHECK(condition, what) ((void)0)
#else
#define PENUMBRA_CHECK(condition, what) \
    ((condition) ? (void)0 : ::penumbra::detail::checkFailed(#condition, what, __FILE__, __LINE__))
#endif
