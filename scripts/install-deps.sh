#!/usr/bin/env bash
# Installs the Debian 12 packages penumbra needs, skipping those already present. Works as root or
# through sudo.
#
#   scripts/install-deps.sh [GROUP...]   groups: build tools test bench fuzz tsan (default: build tools)
#
# It says how much it will download before it starts; apt's own output goes to
# build/install-deps.log.
set -euo pipefail
cd "$(dirname "$0")/.."

# The packages, by what needs them. One group per line of work, so that a user who only renders
# installs only the first two.
declare -A groups
# Compiling penumbra (OpenImageIO is found through pkg-config: see CMakeLists.txt). OpenVDB's
# headers include Boost's and its CMake module asks for Boost.Iostreams, yet Debian's
# libopenvdb-dev depends on neither: libboost-iostreams-dev brings both.
groups[build]="cmake ninja-build g++ pkg-config
    libembree-dev libtbb-dev libopenimageio-dev libopenexr-dev libopencolorio-dev
    libcli11-dev nlohmann-json3-dev libtinyobjloader-dev zlib1g-dev libfmt-dev
    libopenvdb-dev libboost-iostreams-dev"
# `penumbra converge`'s plot (tools/plot_convergence.py). python3-munkres satisfies fonttools's
# "python3-scipy | python3-munkres" with 41 KB rather than SciPy and its dependencies.
groups[tools]="python3 python3-matplotlib python3-munkres"
# The test suite (GoogleTest; Python for the layering check and the README snippet test;
# clang-format for the format check, tests/check_format.py).
# penumbra submit's tests start a real single-node Slurm cluster (tests/support/slurm_cluster.sh):
# the scheduler's daemons and commands, and MUNGE for its authentication.
groups[test]="libgtest-dev libgmock-dev python3 clang-format slurm-wlm munge"
# bench/ only: Google Benchmark, Embree's pathtracer, GNU time, and what
# bench/compare_pathtracer.py reads images with (and oiiotool); Blender, whose Cycles bench/time_to_error.py
# renders against.
groups[bench]="libbenchmark-dev embree-tools time python3-numpy python3-openimageio openimageio-tools blender"
# Fuzzing (scripts/fuzz.sh): clang 14 with the libFuzzer and sanitizer runtimes.
groups[fuzz]="clang libclang-rt-14-dev"
# The ThreadSanitizer build (scripts/build-tsan-tbb.sh): "apt-get source" unpacks Debian's oneTBB
# source with dpkg-source, from a .tar.xz.
groups[tsan]="dpkg-dev xz-utils"

selected=("$@")
[ ${#selected[@]} -eq 0 ] && selected=(build tools)
packages=()
for group in "${selected[@]}"; do
    [ -n "${groups[$group]+set}" ] || { echo "penumbra: unknown package group '$group' (build, tools, test, bench, fuzz, tsan)" >&2; exit 2; }
    read -r -a list <<< "$(echo ${groups[$group]})"
    packages+=("${list[@]}")
done

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi
readarray -t missing < <(printf '%s\n' "${missing[@]}" | sort -u)

sudo=""
if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null; then
        echo "penumbra: installing packages needs root, and sudo is not installed. As root, run:" >&2
        echo "    apt-get update && apt-get install --no-install-recommends ${missing[*]}" >&2
        echo "then run this command again." >&2
        exit 1
    fi
    sudo="sudo"
fi

mkdir -p build
log=build/install-deps.log
: > "$log"
export DEBIAN_FRONTEND=noninteractive
echo "penumbra: installing ${missing[*]} (apt's output: $log)" >&2
run_logged() {
    if ! "$@" >> "$log" 2>&1; then
        echo "penumbra: error: '$*' failed; the end of $log:" >&2
        tail -n 20 "$log" >&2
        exit 1
    fi
}
run_logged $sudo apt-get update
# What it will take: apt's own summary of a simulated install.
plan=$($sudo apt-get install --assume-no --no-install-recommends "${missing[@]}" 2>&1 || true)
count=$(printf '%s\n' "$plan" | sed -n 's/^\([0-9]*\) upgraded, \([0-9]*\) newly installed.*/\2/p')
# "Need to get 2,048 kB of archives", or "Need to get 0 B/11.5 MB" when apt has some cached.
need=$(printf '%s\n' "$plan" | sed -n 's/^Need to get \(.*\) of archives.*/\1/p')
case $need in
    */*) download="${need%%/*} to download (${need#*/} in all, the rest in apt's cache)" ;;
    *) download="${need:-nothing} to download" ;;
esac
disk=$(printf '%s\n' "$plan" | sed -n 's/^After this operation, \([^ ]* [^ ]*\).*/\1/p')
echo "penumbra: ${count:-?} packages, $download, ${disk:-no more} disk space" >&2
run_logged $sudo apt-get install -y --no-install-recommends "${missing[@]}"
echo "penumbra: packages installed" >&2
