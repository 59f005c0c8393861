#!/usr/bin/env bash
# Builds Debian's own oneTBB, the source of the libtbb-dev installed here (same version, same
# Debian patches), with ThreadSanitizer, for the TSan build (scripts/test-sanitizers.sh tsan).
# Debian's libtbb.so is not instrumented, so TSan sees none of the synchronisation by which TBB
# hands a parallel_for's body to its worker threads and waits for them: every read of what the
# code before a loop wrote looks like a race (docs/fuzzing-and-sanitizers.md). Linked against this
# build, the TSan tests load it in place of Debian's (same soname, libtbb.so.12, so Embree's TBB is
# this one too).
#
#   scripts/build-tsan-tbb.sh DIR
#
# The source comes from Debian's archive through apt ("apt-get source", with the deb-src entries in
# DIR/apt/ rather than the machine's apt configuration; apt checks it against the archive's signed
# index). It is built with oneTBB's own TBB_SANITIZE=thread, with g++ like the rest of the TSan
# build (one TSan runtime in the process), and installed into DIR/install; its CMake package is
# DIR/install/lib/cmake/TBB. Nothing is done when DIR/install already holds this version.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ne 1 ]; then
    echo "usage: scripts/build-tsan-tbb.sh DIR" >&2
    exit 2
fi
mkdir -p "$1"
dir=$(cd "$1" && pwd)

package=$(dpkg-query -W -f='${source:Package}' libtbb-dev)
version=$(dpkg-query -W -f='${source:Version}' libtbb-dev)
stamp="$dir/install/built-from"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$package $version" ]; then
    exit 0
fi
rm -rf "$dir/apt" "$dir/src" "$dir/build" "$dir/install"

# apt with a configuration of its own: deb-src entries for the release this machine runs, its own
# index and cache folders.
codename=$(. /etc/os-release && echo "$VERSION_CODENAME")
mkdir -p "$dir/apt/lists/partial" "$dir/apt/cache/archives/partial" "$dir/apt/sources.list.d" "$dir/src"
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
cat > "$dir/apt/sources.list" <<EOF
deb-src [signed-by=$keyring] http://deb.debian.org/debian $codename main
deb-src [signed-by=$keyring] http://deb.debian.org/debian $codename-updates main
deb-src [signed-by=$keyring] http://deb.debian.org/debian-security $codename-security main
EOF
apt_options=(-o "Dir::Etc::SourceList=$dir/apt/sources.list" -o "Dir::Etc::SourceParts=$dir/apt/sources.list.d"
             -o "Dir::State::Lists=$dir/apt/lists" -o "Dir::Cache=$dir/apt/cache" -o "APT::Sandbox::User=root")
log="$dir/build.log"
: > "$log"
run_logged() {
    if ! "$@" >> "$log" 2>&1; then
        echo "scripts/build-tsan-tbb.sh: '$*' failed; the end of $log:" >&2
        tail -n 20 "$log" >&2
        exit 1
    fi
}
echo "scripts/build-tsan-tbb.sh: building $package $version with ThreadSanitizer in $dir (log: $log)" >&2
run_logged apt-get "${apt_options[@]}" update
(cd "$dir/src" && run_logged apt-get "${apt_options[@]}" source --only-source "$package=$version")
source_dir=$(find "$dir/src" -mindepth 1 -maxdepth 1 -type d | head -n 1)

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# Only libtbb: tbbmalloc is not used by penumbra or Embree; no tests (TBB_TEST would build
# oneTBB's own suite), warnings not errors (TBB_STRICT).
run_logged cmake -S "$source_dir" -B "$dir/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_INSTALL_PREFIX="$dir/install" -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_STRICT=OFF \
    -DTBBMALLOC_BUILD=OFF -DTBB4PY_BUILD=OFF
run_logged cmake --build "$dir/build" --parallel "$(nproc)"
run_logged cmake --install "$dir/build"
echo "$package $version" > "$stamp"
