#!/usr/bin/env bash
# The whole test suite again in an optimised build with the invariant checks on (PENUMBRA_CHECK,
# core/check.h), in build-checks/. CI runs it after scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build tools test
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f build-checks/CMakeCache.txt ]; then
    cmake -S . -B build-checks "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_CHECKS=ON
fi
cmake --build build-checks --parallel "$(nproc)"
status=0
ctest --test-dir build-checks --output-on-failure --parallel "$(nproc)" "$@" || status=$?
scripts/skip-reasons.sh build-checks
exit $status
