#!/usr/bin/env python3
"""Writes scenes/instancing.json: two prototype meshes (a faceted pebble and a twisted spire)
placed 600 times over a floor, each instance turned, scaled and given one of five materials.
Deterministic (a fixed seed), so the file only changes when this script does."""
import json
import math
import random
import sys

rng = random.Random(21)


def pebble():
    # An icosahedron subdivided twice, its vertices pushed out to a lumpy radius.
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
             (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(2):
        cache, out = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(verts[a][k] + verts[b][k]) / 2 for k in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                verts.append(tuple(x / n for x in m))
                cache[key] = len(verts) - 1
            return cache[key]

        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = out
    positions = []
    for x, y, z in verts:
        r = 1 + 0.12 * math.sin(3 * x + 1) * math.cos(2 * z) + 0.08 * math.sin(5 * y)
        positions.append([round(x * r, 5), round(0.7 * y * r + 0.6, 5), round(z * r, 5)])
    return positions, [i for f in faces for i in f]


def spire():
    # A hexagonal prism, twisted and tapered as it rises, closed by a point; base on y = 0.
    sides, levels, positions, indices = 6, 8, [], []
    for j in range(levels + 1):
        h = j / levels
        radius = 0.45 * (1 - 0.7 * h)
        for i in range(sides):
            a = 2 * math.pi * i / sides + 1.2 * h
            positions.append([round(radius * math.cos(a), 5), round(2.2 * h, 5), round(radius * math.sin(a), 5)])
    for j in range(levels):
        for i in range(sides):
            a, b = j * sides + i, j * sides + (i + 1) % sides
            c, d = a + sides, b + sides
            indices += [a, c, b, b, c, d]  # counter-clockwise seen from outside
    top = len(positions)
    positions.append([0, 2.6, 0])
    for i in range(sides):
        indices += [levels * sides + i, top, levels * sides + (i + 1) % sides]
    return positions, indices


pebble_p, pebble_i = pebble()
spire_p, spire_i = spire()
materials = ["terracotta", "glaze", "gold", "cream", "copper"]
shapes = [{"type": "quad", "corner": [-40, 0, 40], "edge1": [80, 0, 0], "edge2": [0, 0, -80], "material": "floor"},
          {"type": "quad", "corner": [-6, 9, -10], "edge1": [12, 0, 0], "edge2": [0, 0, 12], "material": "lamp",
           "emission": {"radiance": [3, 2.8, 2.5]}}]
count = 0
for row in range(30):
    for column in range(20):
        x = (column - 9.5) * 0.9 + rng.uniform(-0.3, 0.3)
        z = 3.5 - row * 0.9 + rng.uniform(-0.3, 0.3)
        prototype = "spire" if rng.random() < 0.3 else "pebble"
        scale = rng.uniform(0.22, 0.42)
        shapes.append({"type": "instance", "prototype": prototype, "material": materials[rng.randrange(5)],
                       "transform": [{"scale": round(scale, 3)},
                                     {"rotate": {"axis": [0, 1, 0], "degrees": rng.randrange(360)}},
                                     {"translate": [round(x, 3), 0, round(z, 3)]}]})
        count += 1

scene = {
    "camera": {"look_from": [0, 3.2, 8.5], "look_at": [0, 0.3, -4], "fov": 42},
    "film": {"resolution": [640, 360], "spp": 64},
    "integrator": {"max_depth": 8},
    "background": [0.35, 0.4, 0.5],
    "materials": {
        "floor": {"type": "lambert", "albedo": [0.62, 0.6, 0.56]},
        "lamp": {"type": "lambert", "albedo": 0},
        "terracotta": {"type": "lambert", "albedo": [0.62, 0.27, 0.14]},
        "glaze": {"type": "coated_diffuse", "albedo": [0.08, 0.2, 0.5], "roughness": 0.15},
        "gold": {"type": "rough_conductor", "eta": [0.143, 0.374, 1.442], "k": [3.983, 2.385, 1.603],
                 "roughness": 0.3},
        "cream": {"type": "lambert", "albedo": [0.8, 0.76, 0.66]},
        "copper": {"type": "rough_conductor", "eta": [0.2, 0.92, 1.1], "k": [3.91, 2.45, 2.14], "roughness": 0.45}
    },
    "prototypes": {
        "pebble": {"type": "triangle_mesh", "positions": pebble_p, "indices": pebble_i},
        "spire": {"type": "triangle_mesh", "positions": spire_p, "indices": spire_i}
    },
    "shapes": shapes,
}
header = ("// Instancing (docs/instancing.png): two prototype meshes, a faceted pebble (%d triangles) and a\n"
          "// twisted spire (%d), placed %d times, each instance turned, scaled and given one of five\n"
          "// materials; every mesh is stored and built once. Written by scripts/make-instancing-scene.py.\n"
          % (len(pebble_i) // 3, len(spire_i) // 3, count))
with open(sys.argv[1] if len(sys.argv) > 1 else "scenes/instancing.json", "w") as out:
    # One section, material, prototype or shape a line.
    out.write(header + "{\n")
    parts = []
    for key in ("camera", "film", "integrator", "background"):
        parts.append('    "%s": %s' % (key, json.dumps(scene[key])))
    for key in ("materials", "prototypes"):
        inner = ",\n".join('        "%s": %s' % (k, json.dumps(v)) for k, v in scene[key].items())
        parts.append('    "%s": {\n%s\n    }' % (key, inner))
    inner = ",\n".join("        " + json.dumps(s) for s in scene["shapes"])
    parts.append('    "shapes": [\n%s\n    ]' % inner)
    out.write(",\n".join(parts) + "\n}\n")
