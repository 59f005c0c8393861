#!/usr/bin/env bash
# The sanitizer builds (docs/fuzzing-and-sanitizers.md):
#  - "asan", build-asan/: AddressSanitizer + UndefinedBehaviorSanitizer (g++, -O1, invariant checks
#    on) over the test programs of the parsers, the film, the BVH and the render loop, and the
#    command-line program end to end on hostile input. CI runs it after the test suites.
#  - "tsan", build-tsan/: ThreadSanitizer over the render loop's tests (determinism across thread
#    counts, resume and checkpoints), with tests/tsan.supp. Not clean with Debian's uninstrumented
#    TBB (the document says why), so CI does not run it.
# Any report fails the run. Argument: "asan" or "tsan" to run one of them (default: both).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build tools test

# The CLI (the end-to-end hostile input tests run it) and the test programs of each build.
asan_targets=(penumbra penumbra_scenes_test materials_loader_test film_exr_test film_merge_test hostile_film_test
            pixel_accumulator_test geometry_test bvh_test bvh_motion_test integrator_test render_job_test
            hostile_input_test)
tsan_targets=(integrator_test render_job_test)

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# build_and_test DIR SANITIZERS TARGETS...: configures (once), builds the targets and runs the tests
# of those that are test programs.
build_and_test() {
    local dir=$1 sanitizers=$2
    shift 2
    if [ ! -f "$dir/CMakeCache.txt" ]; then
        cmake -S . -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
            -DPENUMBRA_SANITIZE="$sanitizers"
    fi
    cmake --build "$dir" --parallel "$(nproc)" --target "$@"
    local tests=() labels
    for t in "$@"; do [[ $t == *_test ]] && tests+=("$t"); done
    labels="^($(IFS='|'; echo "${tests[*]}"))\$"
    ctest --test-dir "$dir" -L "$labels" --output-on-failure --parallel "$(nproc)"
}

supp="$PWD/tests"
if [ "${1:-asan}" = asan ]; then
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1"
    export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    build_and_test build-asan address,undefined "${asan_targets[@]}"
fi
if [ "${1:-tsan}" = tsan ]; then
    export TSAN_OPTIONS="suppressions=$supp/tsan.supp:halt_on_error=1:second_deadlock_stack=1"
    build_and_test build-tsan thread "${tsan_targets[@]}"
fi
