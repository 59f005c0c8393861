#!/usr/bin/python3
"""Time to equal RMSE of next-event estimation's light choice among many lights: the light tree
(`"light_sampler": "bvh"`, the default: lights/light_tree.h) against the choice by power alone
(`"power"`, what penumbra did beyond 16 emitters before the tree), on scenes with hundreds of
emitters. Run with Debian's Python (python3-numpy, python3-openimageio):

    /usr/bin/python3 bench/light_sampler.py [--penumbra build/tools/penumbra] [--threads 2]
        [--res 320x240] [--ladder 1,2,...,256] [--reps 4] [--reference-spp 4096] [-o bench/results]

Scenes (written out by this script, `--keep DIR` keeps them):
  - lamps: a room lit by 256 small ceiling lamps (512 triangle lights) of different brightness and
    tint, with 12 boxes on the floor casting shadows;
  - bulbs: 300 point lights at different heights over a floor with 40 spheres.
Per scene: a reference with the tree at --reference-spp as two halves with seeds of their own (the
halves' difference estimates its own noise, subtracted from each MSE: time_to_error.py's
corrected_mse); then each sampler at every rung of --ladder, --reps times with different seeds,
the two samplers alternating; per rung the median time and the RMSE of the mean MSE. The ratio is
the tree's time to the RMSE the power choice reaches at its top rung, interpolated on the tree's
log-log curve of RMSE against time, over the power choice's time at that rung: wall time of the
whole `penumbra render` process, and CPU time (user + system) beside it, since the machine is
shared. The image means of the two samplers' top rungs are compared with the reference's (both
estimate the same image).
"""
import argparse
import json
import math
import os
import random
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from time_to_error import (corrected_mse, machine_description, parse_ladder, read_rgb,  # noqa: E402
                           reference_from_halves, run_penumbra, summarize, time_at_rmse)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def quad(corner, edge1, edge2, material, emission=None):
    shape = {"type": "quad", "corner": corner, "edge1": edge1, "edge2": edge2, "material": material}
    if emission is not None:
        shape["emission"] = {"radiance": emission}
    return shape


def box(center, half, material):
    """Five faces of an axis-aligned box standing on the floor (the bottom is never seen)."""
    (cx, cy, cz), (hx, hy, hz) = center, half
    x0, x1, y0, y1, z0, z1 = cx - hx, cx + hx, cy - hy, cy + hy, cz - hz, cz + hz
    return [quad([x0, y1, z0], [0, 0, 2 * hz], [2 * hx, 0, 0], material),   # top, +y
            quad([x0, y0, z1], [2 * hx, 0, 0], [0, 2 * hy, 0], material),   # front, +z
            quad([x0, y0, z0], [0, 2 * hy, 0], [2 * hx, 0, 0], material),   # back, -z
            quad([x1, y0, z0], [0, 2 * hy, 0], [0, 0, 2 * hz], material),   # right, +x
            quad([x0, y0, z0], [0, 0, 2 * hz], [0, 2 * hy, 0], material)]   # left, -x


def lamps_scene():
    rng = random.Random(7)
    shapes = [quad([-10, 0, -10], [0, 0, 20], [20, 0, 0], "floor"),
              quad([-10, 0, -10], [20, 0, 0], [0, 4, 0], "wall"),
              quad([-10, 0, -10], [0, 4, 0], [0, 0, 20], "wall"),
              quad([10, 0, -10], [0, 0, 20], [0, 4, 0], "wall")]
    for i in range(16):
        for j in range(16):
            x, z = -9.0 + 18.0 * (i + 0.5) / 16, -9.0 + 18.0 * (j + 0.5) / 16
            strength = rng.uniform(2.0, 40.0)
            tint = [rng.uniform(0.6, 1.0), rng.uniform(0.6, 1.0), rng.uniform(0.6, 1.0)]
            # Facing down: edge2 x edge1 along -y.
            shapes.append(quad([x - 0.08, 3.9, z - 0.08], [0.16, 0, 0], [0, 0, 0.16], "black",
                               [round(strength * t, 3) for t in tint]))
    for _ in range(12):
        x, z, h = rng.uniform(-8, 8), rng.uniform(-8, 6), rng.uniform(0.3, 1.5)
        shapes += box([round(x, 3), h, round(z, 3)], [rng.uniform(0.3, 0.9), h, rng.uniform(0.3, 0.9)], "box")
    return {
        # Below the lamps and looking down: no lamp is seen directly (their pixels' coverage
        # noise would hide the light choice's).
        "camera": {"look_from": [0, 3.6, 10], "look_at": [0, 0, 2], "up": [0, 1, 0], "fov": 40},
        "film": {"spp": 16, "filter": {"type": "box", "radius": 0.5}},
        "integrator": {"max_depth": 5},
        "materials": {"floor": {"type": "lambert", "albedo": [0.6, 0.55, 0.5]},
                      "wall": {"type": "lambert", "albedo": 0.7},
                      "box": {"type": "lambert", "albedo": [0.3, 0.5, 0.7]},
                      "black": {"type": "lambert", "albedo": 0}},
        "shapes": shapes,
    }


def bulbs_scene():
    rng = random.Random(11)
    shapes = [quad([-12, 0, -12], [0, 0, 24], [24, 0, 0], "floor")]
    spheres = []
    for _ in range(40):
        r = round(rng.uniform(0.2, 0.7), 3)
        spheres.append(([round(rng.uniform(-9, 9), 3), r, round(rng.uniform(-9, 7), 3)], r))
        shapes.append({"type": "sphere", "center": spheres[-1][0], "radius": r, "material": "ball"})
    lights = []
    while len(lights) < 300:
        position = [round(rng.uniform(-10, 10), 3), round(rng.uniform(0.5, 3.0), 3), round(rng.uniform(-10, 8), 3)]
        # No light within 0.3 of a sphere: a point light grazing a surface lights a few pixels with
        # radiance so high that the MSE of a few repetitions measures those pixels alone.
        if any(math.dist(position, c) < r + 0.3 for c, r in spheres):
            continue
        lights.append({"type": "point", "position": position,
                       "intensity": [round(rng.uniform(0.2, 3.0) * t, 3) for t in (1.0, 0.85, 0.6)]})
    return {
        "camera": {"look_from": [0, 6, 13], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 60},
        "film": {"spp": 16, "filter": {"type": "box", "radius": 0.5}},
        "integrator": {"max_depth": 3},
        "materials": {"floor": {"type": "lambert", "albedo": 0.5},
                      "ball": {"type": "lambert", "albedo": [0.7, 0.3, 0.3]}},
        "shapes": shapes,
        "lights": lights,
    }


SCENES = {"lamps": lamps_scene, "bulbs": bulbs_scene}
SAMPLERS = ("bvh", "power")


def write_scene(folder, name, sampler, res):
    scene = SCENES[name]()
    scene["integrator"]["light_sampler"] = sampler
    width, height = (int(v) for v in res.split("x"))
    scene["film"]["resolution"] = [width, height]
    path = os.path.join(folder, f"{name}-{sampler}.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def measure(args, folder, name):
    files = {s: write_scene(folder, name, s, args.res) for s in SAMPLERS}
    half = args.reference_spp // 2
    halves = []
    for seed in (1001, 1002):
        out = os.path.join(folder, f"{name}-reference-{seed}.exr")
        run_penumbra(args.penumbra, files["bvh"], out, args.threads, half, seed)
        halves.append(read_rgb(out))
    reference, _, reference_noise = reference_from_halves(*halves)
    ladder = parse_ladder(args.ladder)
    runs = {s: [] for s in SAMPLERS}
    top_means = {s: [] for s in SAMPLERS}
    for spp in ladder:
        for rep in range(args.reps):
            order = SAMPLERS if rep % 2 == 0 else tuple(reversed(SAMPLERS))
            for sampler in order:
                out = os.path.join(folder, f"{name}-{sampler}-{spp}-{rep}.exr")
                seconds, info = run_penumbra(args.penumbra, files[sampler], out, args.threads, spp, 1 + rep)
                image = read_rgb(out)
                runs[sampler].append({"key": spp, "spp": spp, "seconds": seconds,
                                      "mse": corrected_mse(image, reference, reference_noise), **info})
                if spp == ladder[-1]:
                    top_means[sampler].append(image.mean(axis=(0, 1)))
                os.remove(out)
        print(f"  {name} {spp} spp done", flush=True)
    curves = {s: summarize(runs[s]) for s in SAMPLERS}
    power_top = curves["power"][-1]
    target = power_top["rmse"]
    bvh_wall = time_at_rmse([(c["seconds"], c["rmse"]) for c in curves["bvh"]], target)
    bvh_cpu = time_at_rmse([(c["cpu_seconds"], c["rmse"]) for c in curves["bvh"]], target)
    return {
        "scene": name, "reference_spp": args.reference_spp, "reference_rmse": math.sqrt(max(reference_noise, 0)),
        "reference_mean": reference.mean(axis=(0, 1)).tolist(),
        "top_means": {s: np.mean(top_means[s], axis=0).tolist() for s in SAMPLERS},
        "curves": curves, "target_rmse": target,
        "power_seconds": power_top["seconds"], "power_cpu_seconds": power_top["cpu_seconds"],
        "bvh_seconds": bvh_wall, "bvh_cpu_seconds": bvh_cpu,
        "wall_ratio": bvh_wall / power_top["seconds"] if bvh_wall else None,
        "cpu_ratio": bvh_cpu / power_top["cpu_seconds"] if bvh_cpu else None,
    }


def fmt(v, digits=3):
    return "n/a" if v is None else f"{v:.{digits}g}"


def write_table(results, path, command, started, load_before, load_after, tree):
    lines = ["# Light choice among many lights: the tree against power", "",
             f"Measured {started} on {machine_description()}; load average {load_before} before, {load_after} "
             f"after. Binary `build/tools/penumbra` (tree at {tree}).", "",
             f"Command: `{command}`", "",
             "Time to the RMSE that the choice by power reaches at its top rung: the tree's time interpolated on "
             "its log-log curve of RMSE against time, over power's time at that rung (wall time of the whole "
             "process, and CPU time, user + system). RMSE against the tree's reference (two halves, its own "
             "noise subtracted). Image means: the top rung's mean over the repetitions against the reference's, "
             "per channel.", "",
             "| scene | reference spp | power: spp, RMSE, wall s, CPU s | tree: wall s, CPU s to that RMSE | "
             "wall ratio | CPU ratio | means (R/G/B) tree, power vs reference |",
             "|---|---|---|---|---|---|---|"]
    for r in results:
        top = r["curves"]["power"][-1]
        means = " ; ".join(
            f"{s} " + "/".join(f"{m / ref:.3f}" for m, ref in zip(r["top_means"][s], r["reference_mean"]))
            for s in SAMPLERS)
        lines.append(f"| {r['scene']} | {r['reference_spp']} | {int(top['spp'])}, {fmt(r['target_rmse'])}, "
                     f"{fmt(r['power_seconds'])}, {fmt(r['power_cpu_seconds'])} | {fmt(r['bvh_seconds'])}, "
                     f"{fmt(r['bvh_cpu_seconds'])} | {fmt(r['wall_ratio'])} | {fmt(r['cpu_ratio'])} | {means} |")
    lines += ["", "Per rung (median wall s, CPU s, RMSE):", ""]
    for r in results:
        for s in SAMPLERS:
            cells = ", ".join(f"{int(c['spp'])} spp: {c['seconds']:.2f} s / {c['cpu_seconds']:.2f} s / {c['rmse']:.4g}"
                              for c in r["curves"][s])
            lines.append(f"- {r['scene']} {s}: {cells}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--penumbra", default=os.path.join(REPO, "build", "tools", "penumbra"))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--res", default="320x240")
    parser.add_argument("--ladder", default="1,2,...,256")
    parser.add_argument("--reps", type=int, default=4)
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("-o", "--output", default=os.path.join(REPO, "bench", "results"))
    parser.add_argument("--keep", help="keep the scenes and references in this folder")
    args = parser.parse_args()
    started = time.strftime("%Y-%m-%d %H:%M")
    load_before = [round(v, 2) for v in os.getloadavg()]
    tree = os.popen(f"git -C {REPO} rev-parse --short HEAD").read().strip()
    folder = args.keep or tempfile.mkdtemp(prefix="light-sampler-")
    os.makedirs(folder, exist_ok=True)
    results = [measure(args, folder, name) for name in args.scenes.split(",")]
    os.makedirs(args.output, exist_ok=True)
    with open(os.path.join(args.output, "light-sampler.json"), "w") as f:
        json.dump(results, f, indent=1)
    command = "/usr/bin/python3 bench/light_sampler.py " + " ".join(sys.argv[1:])
    write_table(results, os.path.join(args.output, "light-sampler.md"), command.strip(), started, load_before,
                [round(v, 2) for v in os.getloadavg()], tree)
    for r in results:
        print(f"{r['scene']}: wall ratio {fmt(r['wall_ratio'])}, CPU ratio {fmt(r['cpu_ratio'])}")


if __name__ == "__main__":
    main()
