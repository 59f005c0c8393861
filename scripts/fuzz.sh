#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) in build-fuzz/ with clang, AddressSanitizer and UBSan, and
# runs one of them, or each in turn ("all"), for SECONDS.
#
#   scripts/fuzz.sh TARGET|all SECONDS [libFuzzer options...]
#
# Each run starts from the seed corpus in fuzz/corpus/TARGET plus what earlier runs found
# (build-fuzz/corpus/TARGET, kept between runs), with the dictionary fuzz/TARGET.dict, no input
# over 10 s (-timeout), inputs up to 64 KiB and no more than 2 GiB of memory (-rss_limit_mb). A crash, hang or
# out-of-memory leaves the input that caused it in build-fuzz/findings/ and exits non-zero.
# FUZZ_JOBS=N runs N processes of one target at once (libFuzzer -fork).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
    echo "usage: scripts/fuzz.sh TARGET|all SECONDS [libFuzzer options...]" >&2
    exit 2
fi
target=$1 seconds=$2
shift 2

scripts/install-deps.sh build fuzz
if [ ! -f build-fuzz/CMakeCache.txt ]; then
    generator=()
    command -v ninja >/dev/null && generator=(-G Ninja)
    CC=clang CXX=clang++ cmake -S . -B build-fuzz "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DPENUMBRA_FUZZ=ON -DPENUMBRA_CHECKS=ON -DPENUMBRA_BUILD_TESTS=OFF
fi
cmake --build build-fuzz --parallel "$(nproc)" --target fuzzers

if [ "$target" = all ]; then
    read -r -a targets < <(tr ';' ' ' < build-fuzz/fuzzers.txt)
else
    targets=("$target")
fi
status=0
for t in "${targets[@]}"; do
    if [ ! -x "build-fuzz/fuzz/${t}_fuzzer" ]; then
        echo "scripts/fuzz.sh: no fuzz target '$t' (targets: $(cat build-fuzz/fuzzers.txt))" >&2
        exit 2
    fi
    mkdir -p "build-fuzz/corpus/$t" build-fuzz/findings
    echo "== fuzzing $t for $seconds s" >&2
    fork=()
    [ "${FUZZ_JOBS:-1}" -gt 1 ] && fork=(-fork="$FUZZ_JOBS" -ignore_crashes=0)

    # Leaks: libFuzzer checks every input that allocates more than it frees (-detect_leaks, on with
    # LeakSanitizer). LeakSanitizer's own check at the process's exit adds nothing to that and is
    # where its stop-the-world tracer sometimes segfaults (google/sanitizers#1353: seen with the
    # texture plugin's OpenImageIO threads alive), so it is off.
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:leak_check_at_exit=0} \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        "build-fuzz/fuzz/${t}_fuzzer" "build-fuzz/corpus/$t" "fuzz/corpus/$t" \
        -dict="fuzz/$t.dict" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -max_len=65536 -artifact_prefix="build-fuzz/findings/$t-" -print_final_stats=1 "${fork[@]}" "$@" || status=1
done
exit $status
