#!/usr/bin/env bash
# Quick start: installs what is missing, builds, and renders the default scene to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
build/tools/penumbra render scenes/cornell-box.json -o out/cornell-box.exr "$@"
echo "penumbra: images are in $(pwd)/out/ (cornell-box.exr scene-linear, cornell-box.png sRGB)"
