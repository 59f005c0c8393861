#!/usr/bin/env bash
# Quick start: installs what is missing, builds the program (not the test suite), and renders the
# default scene to out/. Arguments are passed to `penumbra render`.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
scripts/build.sh
build/tools/penumbra render scenes/cornell-box.json -o out/cornell-box.exr "$@"
here=$(pwd)
cat <<MESSAGE

penumbra: done in $(( (SECONDS - start) / 60 )) min $(( (SECONDS - start) % 60 )) s. The images are in $here/out/:
  cornell-box.exr (scene-linear, with AOVs and the exact sums) and cornell-box.png (sRGB).
The program is $here/build/tools/penumbra. To run it as \`penumbra\`, either put it on PATH
(for this shell; add the line to ~/.profile to keep it):
    export PATH="$here/build/tools:\$PATH"
or install it (program, plugin and data; the installed tree may be moved anywhere):
    cmake --install build --prefix ~/.local      # ~/.local/bin/penumbra
Then: penumbra render scenes/soft-shadows.json -o out/soft-shadows.exr
MESSAGE
