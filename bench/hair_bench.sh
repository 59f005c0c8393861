#!/usr/bin/env bash
# The hair example (scripts/make-hair-scene.py: 150,000 curves) on both backends in the same run:
# the time to load the scene, to build the traversal structure, to render, and the peak memory.
#
#   bench/hair_bench.sh [PENUMBRA] [RESOLUTION] [SPP]    (defaults: build/tools/penumbra 320x240 16)
#
# Prints one line per backend and the bvh / embree ratios. The scene is made once, in
# scenes/hair/ (ignored by git).
set -euo pipefail
cd "$(dirname "$0")/.."
penumbra=${1:-build/tools/penumbra}
resolution=${2:-320x240}
spp=${3:-16}
scene=scenes/hair/fur-ball.json
[ -f "$scene" ] || python3 scripts/make-hair-scene.py "$scene"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
declare -A render peak
for accel in embree bvh; do
    /usr/bin/time -f "%M %e" -o "$out/time-$accel" "$penumbra" render "$scene" --accel "$accel" --res "$resolution" \
        --spp "$spp" --no-display -q -o "$out/$accel.exr" 2> "$out/log-$accel"
    # The load alone: the same command with a resolution of one pixel and one sample.
    /usr/bin/time -f "%e" -o "$out/load-$accel" "$penumbra" render "$scene" --accel "$accel" --res 1x1 --spp 1 \
        --no-display -q -o "$out/load-$accel.exr" 2>/dev/null
    read -r kb total < "$out/time-$accel"
    load=$(cat "$out/load-$accel")
    peak[$accel]=$kb
    render[$accel]=$(python3 -c "print(round($total - $load, 2))")
    echo "$accel: whole run ${total} s, load and build (1 pixel) ${load} s, render ${render[$accel]} s, peak ${kb} kB"
done
python3 -c "print('bvh / embree: render time %.2f, peak memory %.2f' % (${render[bvh]} / ${render[embree]}, ${peak[bvh]} / ${peak[embree]}))"
