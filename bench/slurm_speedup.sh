#!/usr/bin/env bash
# The speed-up of an 8-part Slurm job array over one render (docs/scale-out.md), on a real
# single-node cluster started on this machine (tests/support/slurm_cluster.sh) and stopped
# afterwards. In the same run: one render on one thread, one render on every core, and
# `penumbra submit --parts 8 --cpus-per-task 1` timed from submission to the merged film.
#
#   bench/slurm_speedup.sh BUILD_DIR [SPP] [RES]     # defaults: 64 480x320 (soft-shadows.json)
set -euo pipefail
build=${1:?usage: slurm_speedup.sh BUILD_DIR [SPP] [RES]}
spp=${2:-64}
res=${3:-480x320}
root="$(cd "$(dirname "$0")/.." && pwd)"
penumbra="$(cd "$build" && pwd)/tools/penumbra"
scene="$root/scenes/soft-shadows.json"
work=$(mktemp -d /tmp/penumbra-speedup-XXXXXX)
cluster="$work/cluster"
trap '"$root/tests/support/slurm_cluster.sh" stop "$cluster"; rm -rf "$work"' EXIT
eval "$("$root/tests/support/slurm_cluster.sh" start "$cluster" $$)"

seconds() { local s; s=$(date +%s.%N); "$@" > /dev/null; echo "$(date +%s.%N) - $s" | bc -l; }
one_thread=$(seconds "$penumbra" render "$scene" --spp "$spp" --res "$res" --threads 1 -q --no-display -o "$work/one1.exr")
all_threads=$(seconds "$penumbra" render "$scene" --spp "$spp" --res "$res" -q --no-display -o "$work/one.exr")

start=$(date +%s.%N)
"$penumbra" submit "$scene" --parts 8 --spp "$spp" --res "$res" --cpus-per-task 1 -o "$work/out.exr" > /dev/null
while [ -n "$(squeue --me --noheader)" ]; do sleep 0.1; done
array=$(echo "$(date +%s.%N) - $start" | bc -l)
[ -f "$work/out.exr" ] || { echo "slurm_speedup.sh: the merge did not run" >&2; cat "$work"/out.parts/logs/*.log >&2; exit 1; }
render_sum=$(grep -h '^rendered' "$work"/out.parts/logs/part-*.log | sed 's/.* in \([0-9.]*\) s (scene build \([0-9.]*\) s).*/\1 + \2/' | paste -sd+ | bc -l)

cores=$(nproc)
printf 'soft-shadows.json %s at %d spp on %d cores\n' "$res" "$spp" "$cores"
printf 'one render, 1 thread:        %6.2f s\n' "$one_thread"
printf 'one render, %d threads:       %6.2f s\n' "$cores" "$all_threads"
printf '8-part array + merge job:    %6.2f s   (parts: %.2f s of rendering and scene builds in all)\n' "$array" "$render_sum"
printf 'speed-up over 1 thread:  %.2f (at most %d)\n' "$(echo "$one_thread / $array" | bc -l)" "$cores"
printf 'speed-up over %d threads: %.2f\n' "$cores" "$(echo "$all_threads / $array" | bc -l)"
printf 'scheduling, start-up and merge (array - parts / %d cores): %.2f s\n' "$cores" "$(echo "$array - $render_sum / $cores" | bc -l)"
