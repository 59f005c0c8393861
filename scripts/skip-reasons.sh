#!/usr/bin/env bash
# Prints why the tests of the last ctest run in BUILD_DIR were skipped: GoogleTest writes the
# reason (GTEST_SKIP's message) into the test's output, which ctest keeps in its log only.
#   scripts/skip-reasons.sh BUILD_DIR
set -euo pipefail
log="$1/Testing/Temporary/LastTest.log"
[ -f "$log" ] || exit 0
# GoogleTest prints "FILE:LINE: Skipped" and the message on the next line.
reasons=$(grep -A1 ': Skipped$' "$log" | grep -v -e ': Skipped$' -e '^--$' | sort | uniq -c || true)
if [ -n "$reasons" ]; then
    echo "Skipped tests, by reason (count, reason):"
    echo "$reasons"
fi
