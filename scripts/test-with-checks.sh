#!/usr/bin/env bash
# The test suite again in an optimised build with the invariant checks on (PENUMBRA_CHECK,
# core/check.h), in build-checks/. CI runs it after scripts/test.sh. Left out: the tests of the
# tooling around renders (a Slurm cluster, the README's commands and its figures, the moved
# install), which run no invariant that the rest does not, and take a third of the suite's time.
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
ctest --test-dir build-checks --output-on-failure --parallel "$(nproc)" \
    --exclude-regex "^SlurmCluster\.|^readme_snippets_test|^docs_figures_test|^install_relocatable_test" "$@" || status=$?
scripts/skip-reasons.sh build-checks
exit $status
