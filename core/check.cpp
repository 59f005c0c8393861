#include "core/check.h"

#include <cstdio>
#include <cstdlib>

namespace penumbra::detail {

void checkFailed(const char* condition, const char* what, const char* file, int line) {
    std::fprintf(stderr, "penumbra: invariant violated at %s:%d: %s (%s)\n", file, line, what, condition);
    std::abort();
}

}  // namespace penumbra::detail
