#!/usr/bin/env bash
# The installed program is relocatable: `cmake --install` into a scratch prefix, the whole tree
# moved elsewhere, and the moved `penumbra` renders (EXR and PNG, so the image plugin and the
# OpenColorIO config are found; a textured scene, so the texture plugin is found; the smoke scene,
# so the volume plugin and its OpenVDB file are found) and runs `converge` with its plot. No path of the source or build
# tree may appear in any installed file.
#   install_test.sh CMAKE BUILD_DIR SOURCE_DIR
set -euo pipefail
cmake=$1 build=$(cd "$2" && pwd) source=$(cd "$3" && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

"$cmake" --install "$build" --prefix "$scratch/prefix" > "$scratch/install.log"
for f in bin/penumbra lib/penumbra/libpenumbra_image_plugin.so lib/penumbra/libpenumbra_texture_plugin.so \
         lib/penumbra/libpenumbra_volume_plugin.so share/penumbra/scenes/volumes/smoke.vdb \
         share/penumbra/ocio/config.ocio share/penumbra/scenes/textures/sky.exr \
         share/penumbra/plot_convergence.py share/penumbra/scenes/cornell-box.json; do
    [ -f "$scratch/prefix/$f" ] || fail "the install has no $f"
done
if grep -rlF -e "$source" -e "$build" "$scratch/prefix"; then
    fail "the files above name the source or build tree"
fi

mv "$scratch/prefix" "$scratch/moved"
penumbra=$scratch/moved/bin/penumbra
mkdir "$scratch/work"
cd "$scratch/work"  # no scenes/ or build/ here
"$penumbra" render "$scratch/moved/share/penumbra/scenes/cornell-box.json" --res 32x32 --spp 4 -o out/cb.exr --quiet
[ -s out/cb.exr ] || fail "no EXR written"
[ -s out/cb.png ] || fail "no PNG written"
# Image textures and an HDR environment: the texture plugin is found in the moved tree too.
"$penumbra" render "$scratch/moved/share/penumbra/scenes/outdoor.json" --res 32x24 --spp 2 -o out/outdoor.exr --quiet
[ -s out/outdoor.png ] || fail "no PNG of the textured scene written"
# An OpenVDB volume: the volume plugin is found in the moved tree too.
"$penumbra" render "$scratch/moved/share/penumbra/scenes/smoke.json" --res 32x20 --spp 2 -o out/smoke.exr --quiet
[ -s out/smoke.png ] || fail "no PNG of the smoke scene written"
"$penumbra" converge "$scratch/moved/share/penumbra/scenes/soft-shadows.json" --spp 1,2,4 --res 24x16 \
    --reference-spp 16 -o out/conv --quiet 2> converge.err || { cat converge.err >&2; fail "converge failed"; }
[ -s out/conv/convergence.csv ] || fail "converge wrote no convergence.csv"
if /usr/bin/python3 -c 'import matplotlib' 2>/dev/null; then
    [ -s out/conv/convergence.png ] || { cat converge.err >&2; fail "converge made no plot"; }
    grep -q warning converge.err && { cat converge.err >&2; fail "converge warned"; }
else
    echo "matplotlib is not installed (scripts/install-deps.sh tools): the plot was not checked"
fi
# An example scene named as in the README, from a folder that has no scenes/: the error points at
# the installed examples. The pbrt-v4 example is installed and renders.
if "$penumbra" render scenes/cornell-box.json --quiet 2> notfound.err; then fail "a missing scene rendered"; fi
grep -qF "$scratch/moved/share/penumbra/scenes/cornell-box.json" notfound.err ||
    { cat notfound.err >&2; fail "the error does not point at the installed example scenes"; }
"$penumbra" render "$scratch/moved/share/penumbra/scenes/pbrt/depth-of-field.pbrt" --res 32x20 --spp 2 -o out/pbrt.exr --quiet
[ -s out/pbrt.png ] || fail "the pbrt-v4 example did not render"
echo "installed, moved, rendered and ran converge from $scratch/moved"
