#!/usr/bin/env python3
"""Writes scenes/hair/fur-ball.json: a procedural groom of 150,000 hair fibers on a ball (one cubic
Bezier segment each, tapered from root to tip, combed outward and drooping under gravity), shaded
with the hair material, under the sky of scenes/textures/sky.exr and a sun.

Usage: make-hair-scene.py [OUTPUT.json] [--curves N]

The groom is a function of its parameters alone (roots on a Fibonacci sphere, every random number a
hash of the fiber's index), so the file is the same on every machine. It is about 14 MB, which is
why it is made rather than kept in the repository.
"""
import argparse
import json
import math
import os

GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))


def unit(index, dimension):
    """A number in [0, 1) from (index, dimension): SplitMix64's finalizer of their combination."""
    z = (index * 0x9E3779B97F4A7C15 + dimension * 0xBF58476D1CE4E5B9 + 0x2545F4914F6CDD1D) & (2**64 - 1)
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & (2**64 - 1)
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & (2**64 - 1)
    z ^= z >> 31
    return (z >> 11) / float(2**53)


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def fiber(i, count, center, radius):
    """The four Bezier control points of fiber i of `count`, and its root and tip widths."""
    # Roots on a Fibonacci sphere, the lowest fifth left bare (the ball rests on the floor).
    y = 1.0 - 2.0 * (i + 0.5) / count * 0.8
    ring = math.sqrt(max(0.0, 1.0 - y * y))
    phi = GOLDEN_ANGLE * i
    n = [ring * math.cos(phi), y, ring * math.sin(phi)]
    root = [center[k] + radius * n[k] for k in range(3)]
    # Combed: the normal turned by up to 35 degrees in a random direction, swept round the ball.
    jitter = normalize([unit(i, 1) - 0.5, unit(i, 2) - 0.5, unit(i, 3) - 0.5])
    swirl = normalize([-n[2], 0.0, n[0]]) if ring > 1e-3 else [1.0, 0.0, 0.0]
    direction = normalize([n[k] + 0.45 * jitter[k] + 0.35 * swirl[k] for k in range(3)])
    length = 0.22 + 0.14 * unit(i, 4)
    droop = 0.7 * length * (0.6 + 0.4 * unit(i, 5))
    p1 = [root[k] + direction[k] * length / 3.0 for k in range(3)]
    p2 = [root[k] + direction[k] * 2.0 * length / 3.0 for k in range(3)]
    p3 = [root[k] + direction[k] * length for k in range(3)]
    p2[1] -= 0.35 * droop
    p3[1] -= droop
    return [root, p1, p2, p3]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("output", nargs="?", default=os.path.join(here, "..", "scenes", "hair", "fur-ball.json"))
    parser.add_argument("--curves", type=int, default=150_000)
    args = parser.parse_args()

    center, radius = [0.0, 0.52, 0.0], 0.34
    points = []
    for i in range(args.curves):
        for p in fiber(i, args.curves, center, radius):
            points.append([round(c, 5) for c in p])
    scene = {
        "camera": {"look_from": [0.35, 1.05, 2.6], "look_at": [0.0, 0.52, 0.0], "fov": 36},
        "film": {"resolution": [640, 480], "spp": 64},
        "integrator": {"max_depth": 24},
        "environment": {"type": "image", "file": "../textures/sky.exr", "scale": 0.6,
                        "rotate": {"axis": [0, 1, 0], "degrees": 70}},
        "lights": [{"type": "directional", "direction": [-0.5, -1.0, -0.45], "irradiance": [3.2, 2.9, 2.5]}],
        "materials": {
            "fur": {"type": "hair", "eumelanin": 0.35, "pheomelanin": 0.9, "beta_m": 0.25, "beta_n": 0.35},
            "ball": {"type": "lambert", "albedo": [0.25, 0.15, 0.1]},
            "floor": {"type": "lambert", "albedo": [0.45, 0.42, 0.38]},
        },
        "shapes": [
            {"type": "quad", "corner": [-10, 0, 10], "edge1": [20, 0, 0], "edge2": [0, 0, -20], "material": "floor"},
            {"type": "sphere", "center": center, "radius": radius, "material": "ball"},
            {"type": "curves", "material": "fur", "curve_type": "cylinder", "width": [0.0032, 0.0006],
             "curve_sizes": [4] * args.curves, "points": points},
        ],
    }
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    with open(args.output, "w", encoding="utf-8") as f:
        f.write("// A fur ball of %d hair fibers, made by scripts/make-hair-scene.py.\n" % args.curves)
        json.dump(scene, f, separators=(",", ":"))
        f.write("\n")
    print("wrote %s (%d curves, %.1f MB)" % (args.output, args.curves, os.path.getsize(args.output) / 1e6))


if __name__ == "__main__":
    main()
