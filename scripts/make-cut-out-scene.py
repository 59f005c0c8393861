#!/usr/bin/python3
"""Writes scenes/textures/leaf.png and scenes/cut-outs.json: cut-outs (a shape's "alpha").

The leaf is a 128 x 128 RGBA image: a green blade with darker veins, its alpha 1 inside the
outline and 0 outside, one texel of antialiased edge. The scene hangs 600 instances of one leaf
card (a quad whose alpha, reflectance and transmittance are the image: a diffuse transmitter)
above a floor with a few objects, lit by the sky
and a low sun through the canopy's gaps; beside them a perforated screen (a quad whose alpha is a
checkerboard). Deterministic. Needs numpy and OpenImageIO's Python module (Debian's
python3-numpy, python3-openimageio)."""
import json
import math
import pathlib
import random

import numpy as np
import OpenImageIO as oiio

ROOT = pathlib.Path(__file__).resolve().parent.parent
SIZE = 128


def leaf_image():
    # u across the blade in [-1, 1], v along it in [0, 1] (v = 0 at the stem, the image's bottom row).
    v, u = np.meshgrid((np.arange(SIZE)[::-1] + 0.5) / SIZE, (np.arange(SIZE) + 0.5) / SIZE * 2 - 1, indexing="ij")
    t = np.clip((v - 0.04) / 0.94, 0.0, 1.0)
    half_width = 0.92 * np.sin(math.pi * t) ** 0.75 * (1.0 - 0.35 * t)
    texel = 2.0 / SIZE
    alpha = np.clip((half_width - np.abs(u)) / texel + 0.5, 0.0, 1.0)
    stem = (np.abs(u) < 0.035) & (v < 0.08)
    alpha = np.maximum(alpha, stem.astype(float))
    # Veins: the midrib and pairs of side veins running up and out from it.
    midrib = np.exp(-(u / 0.03) ** 2)
    side = np.exp(-((np.mod(v - 0.55 * np.abs(u), 0.12) - 0.06) / 0.012) ** 2) * (np.abs(u) < half_width * 0.9)
    shade = 1.0 - 0.35 * np.maximum(midrib, 0.6 * side)
    green = np.stack([0.16 + 0.10 * t, 0.42 + 0.12 * t, 0.10 + 0.02 * t], axis=-1) * shade[..., None]
    rgba = np.concatenate([green, alpha[..., None]], axis=-1)
    return (np.clip(rgba, 0, 1) * 255 + 0.5).astype(np.uint8)


def write_leaf(path):
    pixels = leaf_image()
    out = oiio.ImageOutput.create(str(path))
    spec = oiio.ImageSpec(SIZE, SIZE, 4, oiio.UINT8)
    spec.attribute("oiio:UnassociatedAlpha", 1)
    out.open(str(path), spec)
    out.write_image(pixels)
    out.close()


def canopy(rng, count):
    shapes = []
    for _ in range(count):
        x, z = rng.uniform(-3.4, 3.4), rng.uniform(-2.6, 2.0)
        y = rng.uniform(2.4, 3.2) - 0.05 * (x * x + z * z) / 4
        shapes.append({
            "type": "instance", "prototype": "leaf", "material": "leaf",
            "transform": [
                {"scale": round(rng.uniform(0.75, 1.25), 3)},
                {"rotate": {"axis": [1, 0, 0], "degrees": round(rng.uniform(-35, 35), 2)}},
                {"rotate": {"axis": [0, 0, 1], "degrees": round(rng.uniform(-35, 35), 2)}},
                {"rotate": {"axis": [0, 1, 0], "degrees": round(rng.uniform(0, 360), 2)}},
                {"translate": [round(x, 4), round(y, 4), round(z, 4)]},
            ],
        })
    return shapes


def scene():
    rng = random.Random(20261128)
    leaf_texture = {"type": "image", "file": "textures/leaf.png", "filter": "bilinear"}
    return {
        "camera": {"look_from": [0.0, 1.55, 6.2], "look_at": [0.0, 1.0, 0.0], "fov": 42},
        "film": {"resolution": [640, 360], "spp": 64},
        "integrator": {"max_depth": 6},
        "environment": {"type": "image", "file": "textures/sky.exr", "scale": 0.5,
                        "rotate": {"axis": [0, 1, 0], "degrees": 40}},
        "materials": {
            "floor": {"type": "lambert", "albedo": [0.62, 0.58, 0.52]},
            # Thin leaves let the sun through: lit from behind they glow.
            "leaf": {"type": "diffuse_transmission", "reflectance": leaf_texture,
                     "transmittance": dict(leaf_texture, scale=0.8)},
            "clay": {"type": "coated_diffuse", "albedo": [0.7, 0.34, 0.2], "roughness": 0.3},
            "screen": {"type": "lambert", "albedo": [0.75, 0.72, 0.66]},
        },
        "prototypes": {
            # The card spans u across [-0.35, 0.35] and the blade's length along v, stem at the origin.
            "leaf": {"type": "quad", "corner": [-0.17, 0.0, 0.0], "edge1": [0.34, 0.0, 0.0],
                     "edge2": [0.0, 0.0, -0.42], "alpha": leaf_texture},
        },
        "lights": [{"type": "directional", "direction": [-0.45, -1.0, -0.35], "irradiance": [3.4, 3.1, 2.6]}],
        "shapes": [
            {"type": "quad", "corner": [-20, 0, 20], "edge1": [40, 0, 0], "edge2": [0, 0, -40], "material": "floor"},
            {"type": "sphere", "center": [-1.1, 0.55, 0.3], "radius": 0.55, "material": "clay"},
            {"type": "sphere", "center": [0.9, 0.35, 0.9], "radius": 0.35, "material": "clay"},
            # A perforated screen: a checkerboard of coverage 1 and 0, 14 x 10 holes.
            {"type": "quad", "corner": [1.3, 0.0, -1.4], "edge1": [1.8, 0.0, 0.9], "edge2": [0.0, 1.8, 0.0],
             "material": "screen",
             "alpha": {"type": "checkerboard", "colors": [1, 0], "uv_scale": [14, 14]}},
        ] + canopy(rng, 600),
    }


def main():
    write_leaf(ROOT / "scenes" / "textures" / "leaf.png")
    header = ("// Cut-outs (docs/cut-outs.png): 600 leaf cards, instances of one quad whose alpha is\n"
              "// textures/leaf.png (its alpha channel cuts the outline) and whose diffuse reflectance and\n"
              "// transmittance are its colours, over a floor lit by the sky and the sun through the canopy,\n"
              "// beside a screen perforated by a checkerboard alpha. Written by scripts/make-cut-out-scene.py.\n")
    (ROOT / "scenes" / "cut-outs.json").write_text(header + json.dumps(scene()) + "\n")


if __name__ == "__main__":
    main()
