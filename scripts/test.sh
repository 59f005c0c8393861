#!/usr/bin/env bash
# Installs what is missing, builds the program and the test suite, and runs it with ctest. At the
# end it says why tests were skipped (ctest itself lists them without the reason).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh --tests
status=0
ctest --test-dir build --output-on-failure --parallel "$(nproc)" "$@" || status=$?
scripts/skip-reasons.sh build
exit $status
