#!/usr/bin/env python3
"""Writes scenes/subdivision.json: subdivision surfaces. One coarse control mesh, a torus of
8 x 4 quads (64 triangles), shown as it is and as Loop surfaces refined one level and four levels
(moved to the limit surface each time), beside a cube's 6 quads as a Catmull-Clark surface refined
four levels. Deterministic."""
import json
import math
import sys


def torus(segments=8, sides=4, major=1.0, minor=0.42):
    positions, indices = [], []
    for i in range(segments):
        a = 2 * math.pi * i / segments
        for j in range(sides):
            b = 2 * math.pi * j / sides + math.pi / sides
            r = major + minor * math.cos(b)
            positions.append([round(r * math.cos(a), 5), round(minor * math.sin(b), 5), round(r * math.sin(a), 5)])
    for i in range(segments):
        for j in range(sides):
            p00 = i * sides + j
            p10 = ((i + 1) % segments) * sides + j
            p01 = i * sides + (j + 1) % sides
            p11 = ((i + 1) % segments) * sides + (j + 1) % sides
            indices += [p00, p01, p11, p00, p11, p10]  # outward: counter-clockwise seen from outside
    return positions, indices


def cube_quads():
    positions = [[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
    indices = [0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5]
    return positions, indices


def shape(mesh, material, levels, translate, scale, scheme="loop"):
    positions, indices = mesh
    s = {"type": "triangle_mesh", "positions": positions, "indices": indices, "material": material,
         "transform": [{"scale": scale}, {"rotate": {"axis": [1, 0, 0], "degrees": 28}}, {"translate": translate}]}
    if scheme == "catmull_clark":
        s["face_sizes"] = [4] * (len(indices) // 4)
    if levels is not None:
        s["subdivision"] = {"scheme": scheme, "levels": levels}
    return s


scene = {
    "camera": {"look_from": [0, 3.4, 9.0], "look_at": [0, 0.55, 0], "fov": 34},
    "film": {"resolution": [640, 300], "spp": 64},
    "integrator": {"max_depth": 8},
    "background": [0.32, 0.36, 0.42],
    "materials": {
        "floor": {"type": "lambert", "albedo": [0.6, 0.58, 0.55]},
        "lamp": {"type": "lambert", "albedo": 0},
        "clay": {"type": "coated_diffuse", "albedo": [0.62, 0.3, 0.16], "roughness": 0.25},
        "jade": {"type": "coated_diffuse", "albedo": [0.18, 0.45, 0.3], "roughness": 0.1},
    },
    "shapes": [
        {"type": "quad", "corner": [-30, 0, 30], "edge1": [60, 0, 0], "edge2": [0, 0, -60], "material": "floor"},
        {"type": "quad", "corner": [-4, 7, -3], "edge1": [8, 0, 0], "edge2": [0, 0, 6], "material": "lamp",
         "emission": {"radiance": [4.5, 4.3, 4.0]}},
        shape(torus(), "clay", None, [-3.65, 0.75, 0], 1.0),
        shape(torus(), "clay", 1, [-0.95, 0.75, 0], 1.0),
        shape(torus(), "clay", 4, [1.65, 0.75, 0], 1.0),
        shape(cube_quads(), "jade", 4, [4.0, 0.75, 0], 0.95, "catmull_clark"),
    ],
}

text = json.dumps(scene, separators=(", ", ": "))
header = ("// Subdivision surfaces (docs/subdivision.png): a torus of 64 triangles as it is, as Loop surfaces\n"
          "// refined one level and four levels, and a cube's 6 quads as a Catmull-Clark surface refined four\n"
          "// levels. Written by scripts/make-subdivision-scene.py.\n")
out = sys.argv[1] if len(sys.argv) > 1 else "scenes/subdivision.json"
with open(out, "w") as f:
    f.write(header + text + "\n")
