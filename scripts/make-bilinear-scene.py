#!/usr/bin/env python3
"""Writes scenes/bilinear-patches.json: bilinear patches (geometry/bilinear_patches.h). A saddle
z = x y that is one patch, beside the same four corners as two triangles; a twisted band of 48
patches whose edges turn half a turn round a ring; and a coarse torus of 16 x 8 patches, each
curved, with its vertex normals. Deterministic."""
import json
import math
import sys


def saddle_corners(size):
    # p00, p10, p01, p11 of z = x y over [-1, 1]^2 (scaled): one patch is exactly that surface.
    return [[-size, size, -size], [size, -size, -size], [-size, -size, size], [size, size, size]]


def twisted_band(segments=48, radius=1.25, half_width=0.42):
    positions, indices = [], []
    for i in range(segments + 1):
        a = 2 * math.pi * i / segments
        twist = a / 2  # half a turn around the ring
        centre = [radius * math.cos(a), 0.0, radius * math.sin(a)]
        across = [math.cos(twist) * math.cos(a), math.sin(twist), math.cos(twist) * math.sin(a)]
        for side in (-1, 1):
            positions.append([round(centre[k] + side * half_width * across[k], 5) for k in range(3)])
    for i in range(segments):
        indices += [2 * i, 2 * i + 2, 2 * i + 1, 2 * i + 3]
    return positions, indices


def torus(segments=16, sides=8, major=1.0, minor=0.45):
    positions, normals, indices = [], [], []
    for i in range(segments):
        a = 2 * math.pi * i / segments
        for j in range(sides):
            b = 2 * math.pi * j / sides
            r = major + minor * math.cos(b)
            positions.append([round(r * math.cos(a), 5), round(minor * math.sin(b), 5), round(r * math.sin(a), 5)])
            normals.append([round(math.cos(b) * math.cos(a), 5), round(math.sin(b), 5),
                            round(math.cos(b) * math.sin(a), 5)])
    for i in range(segments):
        for j in range(sides):
            p00 = i * sides + j
            p10 = ((i + 1) % segments) * sides + j
            p01 = i * sides + (j + 1) % sides
            p11 = ((i + 1) % segments) * sides + (j + 1) % sides
            indices += [p00, p10, p01, p11]
    return positions, normals, indices


def main():
    place = lambda x: [{"rotate": {"axis": [0, 0, 1], "degrees": 30}}, {"rotate": {"axis": [1, 0, 0], "degrees": -35}},
                       {"translate": [x, 1.2, 0]}]
    corners = saddle_corners(0.9)
    band_positions, band_indices = twisted_band()
    torus_positions, torus_normals, torus_indices = torus()
    scene = {
        "camera": {"look_from": [0, 3.6, 9.5], "look_at": [0, 0.8, 0], "fov": 36},
        "film": {"resolution": [640, 300], "spp": 64},
        "integrator": {"max_depth": 8},
        "background": [0.32, 0.36, 0.42],
        "materials": {
            "floor": {"type": "lambert", "albedo": [0.6, 0.58, 0.55]},
            "lamp": {"type": "lambert", "albedo": 0},
            "copper": {"type": "coated_diffuse", "albedo": [0.62, 0.3, 0.16], "roughness": 0.25},
            "slate": {"type": "coated_diffuse", "albedo": [0.2, 0.28, 0.45], "roughness": 0.2},
            "jade": {"type": "coated_diffuse", "albedo": [0.18, 0.45, 0.3], "roughness": 0.1},
        },
        "shapes": [
            {"type": "quad", "corner": [-30, 0, 30], "edge1": [60, 0, 0], "edge2": [0, 0, -60], "material": "floor"},
            {"type": "quad", "corner": [-4, 7, -3], "edge1": [8, 0, 0], "edge2": [0, 0, 6], "material": "lamp",
             "emission": {"radiance": [4.5, 4.3, 4.0]}},
            {"type": "bilinear_mesh", "positions": corners, "indices": [0, 1, 2, 3], "material": "copper",
             "transform": place(-4.3)},
            # The same corners as two triangles (p00, p10, p11) and (p00, p11, p01).
            {"type": "triangle_mesh", "positions": corners, "indices": [0, 1, 3, 0, 3, 2], "material": "copper",
             "transform": place(-2.1)},
            {"type": "bilinear_mesh", "positions": band_positions, "indices": band_indices, "material": "slate",
             "transform": [{"rotate": {"axis": [1, 0, 0], "degrees": 20}}, {"translate": [0.7, 1.0, 0]}]},
            {"type": "bilinear_mesh", "positions": torus_positions, "normals": torus_normals,
             "indices": torus_indices, "material": "jade",
             "transform": [{"rotate": {"axis": [1, 0, 0], "degrees": 28}}, {"translate": [3.9, 0.75, 0]}]},
        ],
    }
    header = ("// Bilinear patches (docs/bilinear-patches.png): a saddle z = x y that is one patch, beside the\n"
              "// same four corners as two triangles; a twisted band of 48 patches; a torus of 16 x 8 curved\n"
              "// patches with vertex normals. Written by scripts/make-bilinear-scene.py.\n")
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/bilinear-patches.json"
    with open(out, "w") as f:
        f.write(header + json.dumps(scene) + "\n")


if __name__ == "__main__":
    main()
