#!/usr/bin/env bash
# Regenerates every image in docs/ from the current code: the example scenes as the README shows
# them (each at its own resolution and samples) and the two convergence studies of the README,
# run with the README's commands. Work files go to out/docs/.
#   scripts/make-docs-images.sh [PENUMBRA]   (default: builds and uses build/tools/penumbra)
# It renders about 250 million samples: some ten minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
penumbra=${1:-}
if [ -z "$penumbra" ]; then
    scripts/build.sh
    penumbra=build/tools/penumbra
fi
out=out/docs
mkdir -p "$out"

for scene in cornell-box depth-of-field soft-shadows motion-blur distribution materials rough-materials outdoor instancing subdivision cut-outs smoke fire subsurface \
    panorama fisheye orthographic; do
    echo "docs/$scene.png"
    "$penumbra" render "scenes/$scene.json" -o "$out/$scene.exr" --quiet
    cp "$out/$scene.png" "docs/$scene.png"
done

# The lens system's image is exposed as through the lens (0.19 of the light at f/2): shown 2.4
# stops brighter; the thin lens beside it has no exposure model.
echo "docs/lens-bokeh.png, docs/lens-bokeh-thin-lens.png"
"$penumbra" render scenes/lens-bokeh.json --exposure 2.4 -o "$out/lens-bokeh.exr" --quiet
cp "$out/lens-bokeh.png" docs/lens-bokeh.png
"$penumbra" render scenes/lens-bokeh.json --patch scenes/patches/thin-lens-bokeh.json \
    -o "$out/lens-bokeh-thin-lens.exr" --quiet
cp "$out/lens-bokeh-thin-lens.png" docs/lens-bokeh-thin-lens.png

echo "docs/convergence-soft-shadows.png, docs/convergence-soft-shadows-strip.png"
"$penumbra" converge scenes/soft-shadows.json --spp 1,2,4,...,256 --seeds 3 --res 160x108 \
    --reference-spp 4096 -o "$out/convergence-soft-shadows"
cp "$out/convergence-soft-shadows/convergence.png" docs/convergence-soft-shadows.png
cp "$out/convergence-soft-shadows/strip.png" docs/convergence-soft-shadows-strip.png

echo "docs/veach-mis-convergence.png"
"$penumbra" converge scenes/veach-mis.json --spp 1,2,4,...,32 --sampler stratified --res 320x180 \
    --strategy mis,bsdf,light --seeds 3 --reference-spp 1024 -o "$out/veach"
cp "$out/veach/convergence.png" docs/veach-mis-convergence.png
