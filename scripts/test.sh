#!/usr/bin/env bash
# Installs what is missing, builds the program and the test suite, and runs it with ctest. At the
# end it says why tests were skipped (ctest itself lists them without the reason).
#   scripts/test.sh            the whole suite (what CI runs)
#   scripts/test.sh --quick    without the slowest tests (references, the README's studies, the
#                              Slurm cluster, the energy integrals): most of the suite in a third
#                              of its time
# Further arguments go to ctest (e.g. -R NAME).
set -euo pipefail
cd "$(dirname "$0")/.."
exclude=()
if [ "${1:-}" = "--quick" ]; then
    shift
    # The tests that take more than 5 s each on the 2-core development machine: 37 of about 900,
    # two thirds of the suite's time (ctest -j spreads the rest).
    slow="^(readme_snippets_test|docs_figures_test|format_test|VeachMisReference\.|CornellReference\.|PbrtScenes\.|SlurmCluster\."
    slow+="|RoughEnergy\.|CoordinateScale\.|InstancingMemory\.|ExampleScenes\.StratifiedSamplingBeats"
    slow+="|AdaptiveAbsolute\.TheImageMeetsItsRmse|BvhAgainstEmbree\.Stanford|PbrtBombFolder\.|HairBsdf\.(White|Samples))"
    exclude=(--exclude-regex "$slow")
fi
scripts/build.sh --tests
status=0
ctest --test-dir build --output-on-failure --parallel "$(nproc)" "${exclude[@]}" "$@" || status=$?
scripts/skip-reasons.sh build
exit $status
