#!/usr/bin/env bash
# Installs missing packages, configures build/ (Release) and builds the penumbra program.
#   scripts/build.sh           the program only (and the packages it and `converge`'s plot need)
#   scripts/build.sh --tests   the program and the test suite (and the packages the tests need)
# PENUMBRA_WARNINGS_AS_ERRORS=ON in the environment configures build/ with warnings as errors (CI).
set -euo pipefail
cd "$(dirname "$0")/.."
tests=OFF
groups=(build tools)
if [ "${1:-}" = "--tests" ]; then
    tests=ON
    groups+=(test)
fi
scripts/install-deps.sh "${groups[@]}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f build/CMakeCache.txt ]; then
    cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_BUILD_TESTS=$tests
elif [ $tests = ON ] && ! grep -q '^PENUMBRA_BUILD_TESTS:BOOL=ON' build/CMakeCache.txt; then
    cmake -S . -B build -DPENUMBRA_BUILD_TESTS=ON
fi
if [ -n "${PENUMBRA_WARNINGS_AS_ERRORS:-}" ]; then
    cmake -S . -B build -DPENUMBRA_WARNINGS_AS_ERRORS="$PENUMBRA_WARNINGS_AS_ERRORS" >/dev/null
fi
if [ $tests = ON ]; then
    cmake --build build --parallel "$(nproc)"
else
    cmake --build build --parallel "$(nproc)" --target penumbra
fi
