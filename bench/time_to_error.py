#!/usr/bin/python3
"""Time to a clean image: penumbra (fixed and adaptive sampling) against Blender's Cycles, at equal
RMSE, on five scenes that exercise distribution effects. Run with Debian's Python (python3-numpy,
python3-openimageio, python3-matplotlib) and Debian's `blender` (3.4; scripts/install-deps.sh
bench installs it):

    /usr/bin/python3 bench/time_to_error.py [--penumbra build/tools/penumbra] [--threads 2]
        [--res 128x128] [--ladder 4,8,...,256] [--reps 3] [--reference-spp 16x the top rung]
        [--min-spp 16] [--scenes dof,...] [-o DIR] [--keep WORKDIR]

For each scene (`SCENES` below: depth of field with hexagonal bokeh, two area lights with wide
penumbrae, motion blur of a rotating and a translating object, a glass sphere with a caustic under
an area light, a homogeneous fog around two objects and a small area light), one description is written out twice: as a penumbra scene file and as a Blender
Python script that builds the same scene for Cycles (BLENDER_SCRIPT; `--keep` keeps both). Then,
per scene:
  1. a reference with each renderer, as two halves with seeds of their own; the difference of the
     halves estimates the reference's own noise per pixel. The references must agree: image means
     (and each channel's) within 1%, and at least 95% of 8x8-pixel block means within 3 standard
     errors of their difference (from that noise) or within 1% (see references_agree);
  2. each renderer at every rung of --ladder, --reps times with different seeds, alternating
     penumbra and Cycles, with the same thread count; penumbra also adaptive after each rung from
     --min-spp on, at the criterion the fixed film's median pixel has at that rung (at most
     twice the rung's samples); and adaptive with the absolute criterion (`--adaptive-error
     absolute`, renderer/adaptive_sampling.h) after each rung, its target the RMSE the fixed
     render reached at that rung (at most 8x the rung's samples in a pixel, at least the smaller
     of the rung and --min-spp);
  3. the RMSE of each image against its own renderer's reference, the reference's noise subtracted
     (corrected_mse); per rung the median time and the RMSE of the mean MSE over the repetitions;
     the time each renderer needs to reach the same RMSE, interpolated on the log-log curve of
     RMSE against time.
The reference's noise: with R reference samples and a top rung of N, its MSE is about N/R times
the top rung's (less with stratification), so R = 16 N by default puts its RMSE at a quarter of
the lowest RMSE on the ladder or below; it is subtracted besides, and drawn dotted in the plots.
penumbra's time is the wall time of the whole `penumbra render` process (start-up, scene load,
BVH build, render, writing the EXR); Cycles' is the render call inside Blender
(`bpy.ops.render.render`, timed in the script: scene sync, BVH build and render; Blender's own
start-up and the writing of the EXR are left out). CPU times (user + system, all threads) are
recorded beside them: on a shared machine they say what the wall times cannot.

What the two scenes share, and where they differ (the closest Cycles equivalents):
  - camera: same position, look-at and vertical field of view (sensor fit vertical, angle_y; the
    resolution is square); thin lens of the same aperture radius (Cycles' radius is lens * 1e-3 /
    (2 f-stop) with the lens in mm and scene units in metres, so f-stop = lens * 1e-3 / (2 radius))
    and focus distance (both measured along the view direction); a hexagonal aperture in both,
    whose rotation differs by 180/blades degrees between the conventions (Cycles puts an edge's
    midpoint on +x at rotation 0, penumbra a corner), which the Cycles side subtracts;
  - film: box filter one pixel wide in both (penumbra `box` radius 0.5, Cycles BOX width 1);
  - path depth: penumbra's max_depth counts scattering vertices (1: direct light only), Cycles'
    bounces count scatterings after the first (0: direct light only), so Cycles gets max_depth - 1
    as max_bounces and as each of its diffuse, glossy, transmission and transparent limits;
    Russian roulette, light selection and MIS are each renderer's own (Cycles 3.4: no light tree,
    large mesh-light triangles sampled by solid angle, light_sampling_threshold left at 0.01, an
    unbiased roulette of weak shadow rays; its default sampling pattern, progressive multi-jitter);
    clamping, filter glossy and denoising are off in Cycles, caustics on;
  - materials: Lambert = Diffuse BSDF (roughness 0); dielectric = Glass BSDF, sharp, same IOR;
    emitters are two-sided in both (Cycles' mesh lights always are), black diffuse plus emission;
  - spheres: analytic in penumbra, UV spheres of 128 x 64 faces with smooth normals in Cycles;
  - motion: penumbra's shutter [0, 1] with transform keys at its ends (rotation by slerp); Cycles'
    shutter of one frame starting at frame 1, with linear keyframes at frames 1 and 2 (the box
    with 4 motion steps, so its rotation is sampled at 9 times);
  - media (the fog scene): a homogeneous medium inside a closed box, the vacuum outside it and the
    camera outside it. penumbra: a triangle-mesh box of `interface` material (no path vertex, no
    bounce) with the medium `inside`, faces wound outwards; the floor and the objects in the fog
    name no medium (no boundaries). Cycles: the same mesh with a material that has only a Volume
    output (no surface shader: a pure volume boundary, crossed without a bounce), Volume Scatter
    (Color white, Density = sigma_s, Anisotropy = g, both Henyey-Greenstein with g > 0 forward)
    plus Volume Absorption (Color black, Density = sigma_a; Cycles' absorption coefficient is
    (1 - Color) x Density), both per scene unit as penumbra's; the material's homogeneous_volume
    on (one step over the whole segment, transmittance in closed form: volume_step_rate and
    volume_max_steps play no part) and its volume_sampling MULTIPLE_IMPORTANCE (distance and
    equiangular sampling, Blender's default; on this scene at 96x96, 64 spp, 2 seeds, its MSE x
    time was 0.85x distance sampling's and 0.70x equiangular's, measured against a rough
    reference). penumbra samples distances by delta tracking (for a homogeneous medium: distance
    sampling), with next-event estimation at medium vertices, and ratio tracking for shadow rays.
    Both count a medium scattering as a bounce like a surface's: Cycles' volume_bounces (default
    0: single scattering only) gets max_depth - 1 like the others, so max_bounces limits both
    kinds together as penumbra's max_depth does; at the last vertex both trace the continuation
    ray through the medium without scattering, for the emission it hits;
  - the world is black in both; Blender's view transform plays no part (the EXR is scene-linear).
Coordinates are penumbra's (y up); Blender gets them rotated about x by 90 degrees (z up).

Writes DIR/time-to-error.json, DIR/time-to-error.md (one row per scene, ending with the ratio
written like `0.42x`) and DIR/time-to-error-SCENE.png (RMSE against time, all four curves).
The fog scene's results are kept apart from the other four's, in bench/results/time-to-error-fog/
(`--scenes fog -o bench/results/time-to-error-fog`), since it was run at another time.
A benchmark, not a test: nothing in tests/ runs it.
"""

import argparse
import json
import math
import resource
import re
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenImageIO as oiio

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# The scenes, described once (penumbra's coordinates: y up, metres).

def quad(corner, edge1, edge2, material, emission=None):
    return {"kind": "quad", "corner": corner, "edge1": edge1, "edge2": edge2, "material": material,
            "emission": emission}


def sphere(center, radius, material, emission=None, motion=None):
    """motion: [translate at open, translate at close] (center then [0, 0, 0])."""
    return {"kind": "sphere", "center": center, "radius": radius, "material": material, "emission": emission,
            "motion": motion}


def box(center, half, material, spin_degrees=None, inside=None):
    """An axis-aligned box; spin_degrees: [at open, at close] rotation about +y, about its centre;
    inside: the medium it bounds (its faces wound outwards, the vacuum outside)."""
    out = {"kind": "box", "center": center, "half": half, "material": material, "spin": spin_degrees}
    return {**out, "inside": inside} if inside else out


FLOOR = quad([-8, 0, 8], [16, 0, 0], [0, 0, -16], "floor")
BASE_MATERIALS = {"floor": {"type": "lambert", "albedo": 0.6}, "black": {"type": "lambert", "albedo": 0.0}}

SCENES = {
    "dof": {
        "what": "depth of field: focused on the front sphere, the others and six small bright spheres behind "
                "it out of focus (hexagonal bokeh, about 12 pixels across at 128x128)",
        # Cycles puts an edge's midpoint of a polygonal aperture on +x at rotation 0, penumbra a corner
        # (regular_polygon_sample against ThinLensCamera::sampleAperture): 180/6 = 30 degrees apart.
        "camera": {"look_from": [0, 1.0, 6], "look_at": [0, 0.5, 0], "fov": 35, "aperture_radius": 0.15,
                   "aperture_blades": 6, "aperture_rotation": 30, "focus_distance": 3.6},
        "depth": 6,
        "materials": {**BASE_MATERIALS, "red": {"type": "lambert", "albedo": [0.75, 0.2, 0.15]},
                      "blue": {"type": "lambert", "albedo": [0.15, 0.3, 0.75]}},
        "shapes": [FLOOR, sphere([-1.2, 0.5, 2.5], 0.5, "red"), sphere([0.2, 0.5, 0.0], 0.5, "blue"),
                   sphere([1.5, 0.5, -3.0], 0.5, "red")]
                  + [sphere([-3 + 1.2 * i, 1.6 + 0.3 * (i % 2), -7], 0.08, "black", emission=[30, 25, 20])
                     for i in range(6)]
                  + [quad([-3, 5, -1], [6, 0, 0], [0, 0, 2], "black", emission=[3, 3, 3])],
    },
    "penumbrae": {
        "what": "two large area lights: wide penumbrae under a box and a sphere",
        "camera": {"look_from": [0, 2.6, 5.5], "look_at": [0, 0.4, 0], "fov": 38},
        "depth": 6,
        "materials": {**BASE_MATERIALS, "box": {"type": "lambert", "albedo": [0.7, 0.6, 0.5]}},
        "shapes": [FLOOR, box([-0.4, 0.5, 0], [0.5, 0.5, 0.5], "box"), sphere([1.3, 0.45, 0.6], 0.45, "box"),
                   quad([-3.0, 2.6, -1.2], [1.2, 0.6, 0], [0, 0, 2.4], "black", emission=[5, 3.6, 2.0]),
                   quad([1.8, 3.0, -1.0], [1.0, 0, 0], [0, 0, 1.6], "black", emission=[2.0, 3.0, 4.5])],
    },
    "motion": {
        "what": "motion blur: a box spinning about y and a sphere translating across the view",
        "camera": {"look_from": [0, 2.2, 6], "look_at": [0, 0.6, 0], "fov": 40, "shutter": [0, 1]},
        "depth": 6,
        "materials": {**BASE_MATERIALS, "orange": {"type": "lambert", "albedo": [0.8, 0.35, 0.1]},
                      "teal": {"type": "lambert", "albedo": [0.1, 0.55, 0.5]}},
        "shapes": [FLOOR, box([-1.2, 0.6, 0], [0.4, 0.4, 0.4], "orange", spin_degrees=[0, 90]),
                   sphere([0, 0, 0], 0.35, "teal", motion=[[0.0, 0.35, 1.2], [1.4, 0.35, 1.2]]),
                   quad([-2, 4, -1], [4, 0, 0], [0, 0, 2], "black", emission=[5, 4.6, 4])],
    },
    "caustic": {
        "what": "a glass sphere under an area light: its caustic on the floor",
        "camera": {"look_from": [0, 2.5, 4.5], "look_at": [0, 0.5, 0], "fov": 35},
        "depth": 8,
        "materials": {**BASE_MATERIALS, "glass": {"type": "dielectric", "eta": 1.5}},
        "shapes": [FLOOR, sphere([0, 0.6, 0], 0.6, "glass"),
                   quad([-0.4, 3.5, -0.4], [0.8, 0, 0], [0, 0, 0.8], "black", emission=[30, 30, 30])],
    },
    "fog": {
        "what": "homogeneous fog (mildly forward-scattering) in a box around a box, a sphere and a small quad "
                "light: the light's glow and the objects' shadows in the fog, and multiple scattering",
        "camera": {"look_from": [0, 1.6, 7.0], "look_at": [0, 0.9, 0], "fov": 40},
        "depth": 6,
        "media": {"fog": {"type": "homogeneous", "sigma_a": 0.02, "sigma_s": 0.15, "g": 0.3}},
        "materials": {**BASE_MATERIALS, "box": {"type": "lambert", "albedo": [0.7, 0.6, 0.5]},
                      "boundary": {"type": "interface"}},
        "shapes": [FLOOR, box([-0.9, 0.5, -0.3], [0.5, 0.5, 0.5], "box"), sphere([1.0, 0.55, 0.6], 0.55, "box"),
                   quad([-0.3, 2.6, -0.3], [0.6, 0, 0], [0, 0, 0.6], "black", emission=[40, 36, 30]),
                   # The fog's bounds: the camera outside, the floor crossing the sides.
                   box([0, 1.75, 0], [4.0, 2.25, 4.0], "boundary", inside="fog")],
    },
}


def box_mesh(center, half):
    cx, cy, cz = center
    hx, hy, hz = half
    positions = [[cx + sx * hx, cy + sy * hy, cz + sz * hz]
                 for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    # Corners indexed x + 2y + 4z; faces wound outwards.
    faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    return positions, faces


# ---------------------------------------------------------------------------------------------
# penumbra's scene file.

def penumbra_scene(scene, width, height, spp):
    shapes = []
    for s in scene["shapes"]:
        emission = {"emission": {"radiance": s["emission"], "two_sided": True}} if s.get("emission") else {}
        if s["kind"] == "quad":
            shapes.append({"type": "quad", "corner": s["corner"], "edge1": s["edge1"], "edge2": s["edge2"],
                           "material": s["material"], **emission})
        elif s["kind"] == "sphere":
            shape = {"type": "sphere", "center": s["center"], "radius": s["radius"], "material": s["material"],
                     **emission}
            if s.get("motion"):
                shape["motion"] = {"transforms": [{"translate": t} for t in s["motion"]]}
            shapes.append(shape)
        elif s["kind"] == "box":
            positions, faces = box_mesh([0, 0, 0] if s.get("spin") else s["center"], s["half"])
            indices = [i for f in faces for i in (f[0], f[1], f[2], f[0], f[2], f[3])]
            shape = {"type": "triangle_mesh", "positions": positions, "indices": indices, "material": s["material"]}
            if s.get("inside"):
                shape["inside"] = s["inside"]
            if s.get("spin"):
                shape["motion"] = {"transforms": [{"rotate": {"axis": [0, 1, 0], "degrees": d},
                                                   "translate": s["center"]} for d in s["spin"]]}
            shapes.append(shape)
    out = {"camera": scene["camera"],
           "film": {"resolution": [width, height], "spp": spp, "filter": {"type": "box", "radius": 0.5}},
           "integrator": {"max_depth": scene["depth"]},
           "materials": scene["materials"], "shapes": shapes}
    if scene.get("media"):
        out["media"] = scene["media"]
    return out


# ---------------------------------------------------------------------------------------------
# Blender: bench/time_to_error_cycles.py, run as `blender -b --factory-startup --python
# time_to_error_cycles.py -- SPEC.json`, builds the scene, renders it with Cycles, times the render
# call and writes the EXR.
BLENDER_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "time_to_error_cycles.py")


# ---------------------------------------------------------------------------------------------
# Running the renderers.

def read_rgb(path):
    return read_channels(path, 0, 3)


def read_channels(path, first, count, subimage=0):
    image = oiio.ImageInput.open(path)
    if image is None:
        raise SystemExit(f"cannot read {path}: {oiio.geterror()}")
    if subimage:
        image.seek_subimage(subimage, 0)
    spec = image.spec()
    pixels = image.read_image(subimage, 0, first, first + count, "float")
    image.close()
    return np.asarray(pixels, dtype=np.float64).reshape(spec.height, spec.width, count)


def median_relative_error(path):
    """The median over the pixels of adaptive sampling's criterion (renderer/adaptive_sampling.h):
    sqrt(mean of the channels' variance of the mean) / (mean of the channels + 0.05), from the
    film's `variance.*` AOV (channels 11 to 13 of part `beauty`)."""
    rgb, variance = read_rgb(path), read_channels(path, 11, 3)
    error = np.sqrt(np.maximum(variance, 0).mean(axis=2)) / (rgb.mean(axis=2) + 0.05)
    return float(np.median(error))


def parse_penumbra_summary(text):
    """What `penumbra render` says at the end: render time, rays and (adaptive) samples."""
    out = {}
    m = re.search(r" in ([0-9.]+) s \(scene build ([0-9.]+) s\)", text)
    if m:
        out["render_s"], out["scene_build_s"] = float(m.group(1)), float(m.group(2))
    m = re.search(r"\(([0-9]+) camera, ([0-9]+) bounce, ([0-9]+) shadow rays\)", text)
    if m:
        out["rays"] = sum(int(g) for g in m.groups())
    m = re.search(r"adaptive [0-9.e+-]+ \((?:image RMSE, )?min [0-9]+ spp\): ([0-9]+) samples, mean ([0-9.]+) spp",
                  text)
    if m:
        out["samples"], out["mean_spp"] = int(m.group(1)), float(m.group(2))
    return out


def run_penumbra(binary, scene_file, out, threads, spp, seed, adaptive=None, min_spp=None, adaptive_error=None):
    """Wall time of the whole process: start-up, scene load, BVH build, render, writing the EXR
    (the default full film, as a user gets it); and its CPU time (user + system, all threads)."""
    cmd = [binary, "render", scene_file, "--spp", str(spp), "--seed", str(seed), "--threads", str(threads),
           "--no-display", "-o", out]
    if adaptive:
        cmd += ["--adaptive", repr(adaptive)]
        if min_spp:
            cmd += ["--min-spp", str(min_spp)]
        if adaptive_error:
            cmd += ["--adaptive-error", adaptive_error]
    start, usage = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds, after = time.perf_counter() - start, resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"penumbra failed: {' '.join(cmd)}\n{proc.stderr}")
    cpu_seconds = (after.ru_utime - usage.ru_utime) + (after.ru_stime - usage.ru_stime)
    return seconds, {"cpu_seconds": cpu_seconds, **parse_penumbra_summary(proc.stdout + proc.stderr)}


def run_cycles(blender, script, spec_file, spec):
    """The render call's wall and CPU time (all threads), measured inside Blender (Blender's
    start-up and the EXR's writing are outside it)."""
    with open(spec_file, "w") as f:
        json.dump(spec, f)
    cmd = [blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script, "--", spec_file]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds, settings = None, {}
    for line in proc.stdout.splitlines():
        if line.startswith("CYCLES_RENDER_SECONDS"):
            seconds, cpu_seconds = float(line.split()[1]), float(line.split()[2])
        if line.startswith("CYCLES_SETTINGS"):
            settings = json.loads(line.split(" ", 1)[1])
    if proc.returncode != 0 or seconds is None or not os.path.exists(spec["output"]):
        raise SystemExit(f"blender failed: {' '.join(cmd)}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return seconds, cpu_seconds, settings


# ---------------------------------------------------------------------------------------------
# Error measures.

def reference_from_halves(a, b):
    """A reference as the mean of two independent halves, and its own noise: with d = (a - b) / 2,
    d_i^2 estimates the variance of pixel i of the mean without bias (Var d_i = (Var a_i + Var b_i)
    / 4 = Var ((a_i + b_i) / 2)), so mean(d^2) is the reference's expected MSE against the
    converged image."""
    d2 = ((a - b) / 2) ** 2
    return (a + b) / 2, d2, float(d2.mean())


def corrected_mse(image, reference, reference_noise_mse):
    """MSE against the converged image, estimated against a noisy reference: E|x - r|^2 = E|x - c|^2
    + E|r - c|^2 for independent x and r, so the reference's own noise is subtracted."""
    return float(np.mean((image - reference) ** 2)) - reference_noise_mse


def references_agree(ref_p, var_p, ref_c, var_c, block=8):
    """Means within 1% (all channels together and each); and the structure: block means (8x8
    pixels, each channel) whose difference is within 3 standard errors, the standard error from the
    two references' own per-pixel noise estimates (0.27% of blocks would exceed 3 with noise alone,
    given normal block means), or within 1% of the block's mean, in at least 95% of the blocks. The
    1% is for differences of the renderers, not of the scenes: Cycles' mesh lights come out up to
    0.8% darker than the closed form on the motion scene's floor, where penumbra is within 0.05%
    (bench/README.md, "time_to_error.py"). Also the fraction within 3 standard errors alone and the
    mean square of the z scores (1 for noise alone)."""
    mean_p, mean_c = float(ref_p.mean()), float(ref_c.mean())
    channel_p, channel_c = ref_p.mean(axis=(0, 1)), ref_c.mean(axis=(0, 1))
    rel = (mean_p - mean_c) / mean_c
    channel_rel = (channel_p - channel_c) / np.maximum(channel_c, 1e-12)
    mean_ok = abs(rel) <= 0.01 and bool(np.all(np.abs(channel_rel) <= 0.01))
    h, w = (ref_p.shape[0] // block) * block, (ref_p.shape[1] // block) * block
    shape = (h // block, block, w // block, block, 3)
    diff = ref_p[:h, :w].reshape(shape).mean(axis=(1, 3)) - ref_c[:h, :w].reshape(shape).mean(axis=(1, 3))
    var = (var_p[:h, :w] + var_c[:h, :w]).reshape(shape).sum(axis=(1, 3)) / block ** 4
    z = np.where(var > 0, diff / np.sqrt(np.maximum(var, 1e-30)), np.where(diff == 0, 0.0, np.inf))
    within = float(np.mean(np.abs(z) <= 3))
    level = ref_c[:h, :w].reshape(shape).mean(axis=(1, 3))
    within_or_1pct = float(np.mean(np.abs(diff) <= 3 * np.sqrt(var) + 0.01 * np.abs(level)))
    finite = np.isfinite(z)
    return {"mean_penumbra": mean_p, "mean_cycles": mean_c, "mean_rel_diff": rel,
            "channel_rel_diff": [float(v) for v in channel_rel], "mean_ok": bool(mean_ok),
            "blocks_within_3se": within, "blocks_within_3se_or_1pct": within_or_1pct,
            "mean_z2": float(np.mean(z[finite] ** 2)), "agree": bool(mean_ok and within_or_1pct >= 0.95)}


def bokeh_spots(image, count=6, top=0.45):
    """The six bokeh spots of the depth-of-field scene, one per sixth of the image's width in its top
    45% (pixels above 5% of the sixth's peak): per spot, the energy, the RMS radius in pixels and
    the phase of the sixth angular harmonic in degrees (a hexagon's orientation, modulo 60). Equal
    radii say the aperture radius and focus distance were translated alike; equal phases, the
    blades' rotation."""
    lum = image.mean(axis=2)[:int(top * image.shape[0])]
    spots = []
    for columns in np.array_split(np.arange(lum.shape[1]), count):
        sub = lum[:, columns]
        ys, xs = np.nonzero(sub > 0.05 * sub.max())
        w = sub[ys, xs]
        dy, dx = ys - (ys * w).sum() / w.sum(), xs - (xs * w).sum() / w.sum()
        r2 = dy ** 2 + dx ** 2
        h6 = (w * r2 * np.exp(6j * np.arctan2(-dy, dx))).sum() / (w * r2).sum()
        spots.append({"energy": float(w.sum()), "rms_radius": float(np.sqrt((w * r2).sum() / w.sum())),
                      "phase_deg": float(np.degrees(np.angle(h6)) / 6)})
    return spots


def time_at_rmse(points, target):
    """Seconds at `target` RMSE on the piecewise-linear log-log curve through (seconds, rmse)
    points taken in order of time; None outside the curve's range."""
    pts = sorted((p for p in points if p[0] > 0 and p[1] > 0), key=lambda p: p[0])
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if min(e0, e1) <= target <= max(e0, e1):
            if e0 == e1:
                return t0
            u = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + u * (math.log(t1) - math.log(t0)))
    return None


def parse_ladder(text):
    """"4,8,...,256" (a "..." continues the ratio of the two numbers before it) or "4,16,64"."""
    parts, values, i = text.split(","), [], 0
    while i < len(parts):
        if parts[i] == "...":
            ratio, last = values[-1] // values[-2], int(parts[i + 1])
            while values[-1] * ratio < last:
                values.append(values[-1] * ratio)
            values.append(last)
            i += 2
            continue
        values.append(int(parts[i]))
        i += 1
    return values


def summarize(runs):
    """Per rung: the median wall time over the repetitions, and the RMSE from the mean of their
    corrected MSEs."""
    out = []
    for key in sorted({r["key"] for r in runs}, key=lambda k: (isinstance(k, str), k)):
        rs = [r for r in runs if r["key"] == key]
        mse = float(np.mean([r["mse"] for r in rs]))
        entry = {"key": key, "seconds": float(np.median([r["seconds"] for r in rs])),
                 "seconds_all": [r["seconds"] for r in rs], "rmse": math.sqrt(max(mse, 1e-30)),
                 "rmse_all": [math.sqrt(max(r["mse"], 1e-30)) for r in rs]}
        cpu = [r["cpu_seconds"] for r in rs if r.get("cpu_seconds") is not None]
        if cpu:
            entry["cpu_seconds"] = float(np.median(cpu))
            entry["cpu_seconds_all"] = cpu
        for extra in ("spp", "mean_spp", "threshold", "rays", "render_s"):
            vals = [r[extra] for r in rs if r.get(extra) is not None]
            if vals:
                entry[extra] = float(np.median(vals))
        out.append(entry)
    return out


def machine_description():
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        mem = next(int(l.split()[1]) for l in open("/proc/meminfo") if l.startswith("MemTotal")) / 2 ** 20
    except (OSError, StopIteration):
        mem = 0
    return f"{model}, {os.cpu_count()} cores, {mem:.1f} GiB"


# ---------------------------------------------------------------------------------------------

def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--penumbra", default=os.path.join(REPO, "build", "tools", "penumbra"))
    parser.add_argument("--blender", default=shutil.which("blender") or "blender")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--res", default="128x128")
    parser.add_argument("--ladder", default="4,8,...,256")
    parser.add_argument("--reps", type=int, default=3, help="repetitions of each rung, alternating the renderers")
    parser.add_argument("--reference-spp", type=int, default=0,
                        help="samples of each reference (two halves); default 16x the top rung")
    parser.add_argument("--min-spp", type=int, default=16, help="penumbra's adaptive --min-spp")
    parser.add_argument("--no-adaptive", action="store_true")
    parser.add_argument("--headline-rung", type=int, default=64,
                        help="the table's row: the RMSE Cycles reaches with this many samples")
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("-o", "--output", default=os.path.join(REPO, "bench", "results"))
    parser.add_argument("--keep", help="keep the scenes and images in this folder")
    parser.add_argument("--write-scenes", metavar="DIR",
                        help="only write each scene for penumbra (NAME.json) and for the Cycles script "
                             "(NAME-cycles.json, at 64 spp), and exit")
    args = parser.parse_args()
    width, height = (int(v) for v in args.res.split("x"))
    ladder = parse_ladder(args.ladder)
    reference_spp = args.reference_spp or 16 * ladder[-1]
    if args.write_scenes:
        os.makedirs(args.write_scenes, exist_ok=True)
        for name in args.scenes.split(","):
            with open(os.path.join(args.write_scenes, f"{name}.json"), "w") as f:
                json.dump(penumbra_scene(SCENES[name], width, height, reference_spp), f, indent=1)
                f.write("\n")
            with open(os.path.join(args.write_scenes, f"{name}-cycles.json"), "w") as f:
                json.dump({"scene": SCENES[name], "spp": 64, "seed": 1, "threads": args.threads, "width": width,
                           "height": height, "output": f"{name}-cycles.exr"}, f, indent=1)
                f.write("\n")
        return 0
    os.makedirs(args.output, exist_ok=True)
    work = args.keep or tempfile.mkdtemp(prefix="penumbra-time-to-error-")
    os.makedirs(work, exist_ok=True)
    script = BLENDER_SCRIPT

    results = {"command": " ".join(["/usr/bin/python3", "bench/time_to_error.py"] + sys.argv[1:]),
               "date": time.strftime("%Y-%m-%dT%H:%M:%S"), "machine": machine_description(),
               "load_before": list(os.getloadavg()), "resolution": [width, height], "threads": args.threads,
               "ladder": ladder, "reps": args.reps, "reference_spp": reference_spp, "min_spp": args.min_spp,
               "headline_rung": args.headline_rung, "scenes": {}}
    started = time.perf_counter()
    for name in args.scenes.split(","):
        scene = SCENES[name]
        log(f"{name}: {scene['what']}")
        scene_file = os.path.join(work, f"{name}.json")
        with open(scene_file, "w") as f:
            json.dump(penumbra_scene(scene, width, height, reference_spp), f, indent=1)
        spec_file = os.path.join(work, f"{name}-cycles.json")
        cycles_settings = {}

        def penumbra(spp, seed, out, **kw):
            return run_penumbra(args.penumbra, scene_file, out, args.threads, spp, seed, **kw)

        def cycles(spp, seed, out):
            seconds, cpu_seconds, settings = run_cycles(
                args.blender, script, spec_file, {"scene": scene, "spp": spp, "seed": seed, "threads": args.threads,
                                                  "width": width, "height": height, "output": out})
            cycles_settings.update(settings)
            return seconds, {"cpu_seconds": cpu_seconds}

        # References: two halves with seeds of their own, alternating the renderers.
        log(f"  references: 2 x {reference_spp // 2} spp each")
        halves = {"penumbra": [], "cycles": []}
        reference_seconds = {"penumbra": 0.0, "cycles": 0.0}
        for seed in (1000, 2000):
            out = os.path.join(work, f"{name}-ref-p-{seed}.exr")
            reference_seconds["penumbra"] += penumbra(reference_spp // 2, seed, out)[0]
            halves["penumbra"].append(read_rgb(out))
            out = os.path.join(work, f"{name}-ref-c-{seed}.exr")
            reference_seconds["cycles"] += cycles(reference_spp // 2, seed, out)[0]
            halves["cycles"].append(read_rgb(out))
        reference, ref_var, ref_noise = {}, {}, {}
        for kind in halves:
            reference[kind], ref_var[kind], ref_noise[kind] = reference_from_halves(*halves[kind])
        agreement = references_agree(reference["penumbra"], ref_var["penumbra"], reference["cycles"],
                                     ref_var["cycles"])
        log(f"  references: means {agreement['mean_penumbra']:.5g} and {agreement['mean_cycles']:.5g} "
            f"({100 * agreement['mean_rel_diff']:+.2f}%), {100 * agreement['blocks_within_3se']:.1f}% of blocks "
            f"within 3 standard errors ({100 * agreement['blocks_within_3se_or_1pct']:.1f}% with 1%), mean z^2 "
            f"{agreement['mean_z2']:.2f}: "
            f"{'agree' if agreement['agree'] else 'DO NOT AGREE'}; own noise RMSE "
            f"{math.sqrt(ref_noise['penumbra']):.3g} and {math.sqrt(ref_noise['cycles']):.3g}")

        if scene["camera"].get("aperture_blades"):
            agreement["bokeh"] = {kind: bokeh_spots(reference[kind]) for kind in reference}
            log("  bokeh RMS radii (px), penumbra / Cycles: " + ", ".join(
                f"{p['rms_radius']:.2f}/{c['rms_radius']:.2f}"
                for p, c in zip(agreement["bokeh"]["penumbra"], agreement["bokeh"]["cycles"])))

        runs = {"penumbra": [], "penumbra adaptive": [], "penumbra adaptive rmse": [], "cycles": []}
        thresholds, targets = {}, {}
        for rep in range(args.reps):
            seed = rep + 1
            for spp in ladder:
                order = ("penumbra", "cycles") if (rep + ladder.index(spp)) % 2 == 0 else ("cycles", "penumbra")
                for kind in order:
                    out = os.path.join(work, f"{name}-{kind[0]}-{spp}-{seed}.exr")
                    if kind == "penumbra":
                        seconds, summary = penumbra(spp, seed, out)
                    else:
                        seconds, summary = cycles(spp, seed, out)
                    image = read_rgb(out)
                    runs[kind].append({"key": spp, "spp": spp, "seconds": seconds,
                                       "mse": corrected_mse(image, reference[kind], ref_noise[kind]), **summary})
                    if kind == "penumbra" and rep == 0:
                        thresholds[spp] = median_relative_error(out)
                        targets[spp] = math.sqrt(max(runs[kind][-1]["mse"], 1e-30))
                # Adaptive at the criterion that the fixed render's median pixel has at this rung:
                # it stops the pixels already as clean and spends on the others (as `converge
                # --adaptive`), up to twice the rung's samples (a bound on its time: the pixels whose
                # relative error stays large, bright bokeh or caustics, would take any maximum).
                if not args.no_adaptive and spp >= args.min_spp:
                    threshold = float(f"{thresholds[spp]:.4g}")
                    out = os.path.join(work, f"{name}-a-{spp}-{seed}.exr")
                    seconds, summary = penumbra(2 * spp, seed, out, adaptive=threshold, min_spp=args.min_spp)
                    runs["penumbra adaptive"].append({"key": spp, "threshold": threshold, "seconds": seconds,
                                                      "mse": corrected_mse(read_rgb(out), reference["penumbra"],
                                                                           ref_noise["penumbra"]), **summary})
                # Adaptive with the absolute criterion: the image RMSE the fixed render reached at
                # this rung as its target (the floor of the minimum everywhere takes it lower), up
                # to 8x the rung's samples in a pixel (where the noise is); below --min-spp the
                # rung is the minimum, so that the curve reaches the low rungs' errors too.
                if not args.no_adaptive:
                    target = float(f"{targets[spp]:.4g}")
                    out = os.path.join(work, f"{name}-r-{spp}-{seed}.exr")
                    seconds, summary = penumbra(8 * spp, seed, out, adaptive=target,
                                                min_spp=max(2, min(args.min_spp, spp)), adaptive_error="absolute")
                    runs["penumbra adaptive rmse"].append({"key": spp, "threshold": target, "seconds": seconds,
                                                           "mse": corrected_mse(read_rgb(out), reference["penumbra"],
                                                                                ref_noise["penumbra"]), **summary})
                p = [r for r in runs["penumbra"] if r["key"] == spp][-1]
                c = [r for r in runs["cycles"] if r["key"] == spp][-1]
                log(f"  rep {rep + 1} {spp:5d} spp: penumbra {p['seconds']:.2f} s RMSE {math.sqrt(max(p['mse'], 0)):.4g}, "
                    f"cycles {c['seconds']:.2f} s RMSE {math.sqrt(max(c['mse'], 0)):.4g}"
                    + (f", adaptive {runs['penumbra adaptive'][-1]['seconds']:.2f} s RMSE "
                       f"{math.sqrt(max(runs['penumbra adaptive'][-1]['mse'], 0)):.4g}"
                       if runs["penumbra adaptive"] and runs["penumbra adaptive"][-1]["key"] == spp else "")
                    + (f", adaptive (image RMSE) {runs['penumbra adaptive rmse'][-1]['seconds']:.2f} s RMSE "
                       f"{math.sqrt(max(runs['penumbra adaptive rmse'][-1]['mse'], 0)):.4g}"
                       if runs["penumbra adaptive rmse"] and runs["penumbra adaptive rmse"][-1]["key"] == spp else ""))
        curves = {kind: summarize(r) for kind, r in runs.items()}

        # Equal error: each Cycles rung's RMSE, reached by penumbra (fixed, adaptive) in how long;
        # and penumbra's adaptive against penumbra's fixed at each fixed rung's RMSE.
        rows = []
        for c in curves["cycles"]:
            row = {"spp": c["key"], "rmse": c["rmse"], "cycles_seconds": c["seconds"],
                   "cycles_cpu_seconds": c.get("cpu_seconds")}
            for kind in ("penumbra", "penumbra adaptive", "penumbra adaptive rmse"):
                key = kind.replace(" ", "_")
                t = time_at_rmse([(p["seconds"], p["rmse"]) for p in curves[kind]], c["rmse"])
                row[key + "_seconds"] = t
                row[key + "_ratio"] = t / c["seconds"] if t else None
                t = time_at_rmse([(p["cpu_seconds"], p["rmse"]) for p in curves[kind]], c["rmse"])
                row[key + "_cpu_seconds"] = t
                row[key + "_cpu_ratio"] = t / c["cpu_seconds"] if t and c.get("cpu_seconds") else None
            rows.append(row)
        def against_fixed(kind):
            out = []
            for p in curves["penumbra"]:
                t = time_at_rmse([(a["seconds"], a["rmse"]) for a in curves[kind]], p["rmse"])
                tc = time_at_rmse([(a["cpu_seconds"], a["rmse"]) for a in curves[kind]], p["rmse"])
                n = time_at_rmse([(a["mean_spp"], a["rmse"]) for a in curves[kind] if a.get("mean_spp")], p["rmse"])
                out.append({"spp": p["key"], "rmse": p["rmse"], "fixed_seconds": p["seconds"],
                            "adaptive_seconds": t, "ratio": t / p["seconds"] if t else None,
                            "cpu_ratio": tc / p["cpu_seconds"] if tc else None,
                            "adaptive_mean_spp": n, "spp_ratio": n / p["key"] if n else None})
            return out
        adaptive_rows, adaptive_rmse_rows = against_fixed("penumbra adaptive"), against_fixed("penumbra adaptive rmse")
        results["scenes"][name] = {
            "what": scene["what"], "agreement": agreement, "cycles_settings": cycles_settings,
            "reference_noise_rmse": {k: math.sqrt(v) for k, v in ref_noise.items()},
            "reference_seconds": reference_seconds, "curves": curves, "equal_error": rows,
            "adaptive_vs_fixed": adaptive_rows, "adaptive_rmse_vs_fixed": adaptive_rmse_rows}
        plot(name, scene["what"], curves, {k: math.sqrt(v) for k, v in ref_noise.items()},
             os.path.join(args.output, f"time-to-error-{name}.png"))
        # Written after every scene, so that a long run leaves what it measured.
        results["load_after"] = list(os.getloadavg())
        results["total_seconds"] = time.perf_counter() - started
        with open(os.path.join(args.output, "time-to-error.json"), "w") as f:
            json.dump(results, f, indent=1)
        write_table(results, os.path.join(args.output, "time-to-error.md"))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 0


def plot(name, what, curves, noise, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 3.6))
    styles = {"penumbra": ("o-", "C0"), "penumbra adaptive": ("s-.", "C2"),
              "penumbra adaptive rmse": ("D:", "C1"), "cycles": ("^--", "C3")}
    for kind, (style, colour) in styles.items():
        pts = sorted(curves[kind], key=lambda p: p["seconds"])
        if not pts:
            continue
        label = "penumbra adaptive (image RMSE)" if kind == "penumbra adaptive rmse" else kind
        ax.plot([p["seconds"] for p in pts], [p["rmse"] for p in pts], style, color=colour, label=label, ms=4)
        for p in pts:  # every repetition, faint
            ax.plot(p["seconds_all"], p["rmse_all"], ".", color=colour, alpha=0.35, ms=3)
    for kind, colour in (("penumbra", "C0"), ("cycles", "C3")):
        ax.axhline(noise[kind], color=colour, ls=":", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("RMSE against own reference")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"{name}: RMSE against time (dotted: references' own noise)", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def fmt_ratio(v):
    return f"{v:.2f}x" if v else "-"


def fmt_s(v):
    return f"{v:.2f}" if v else "-"


def write_table(results, path):
    """The headline table: one row per scene, at the RMSE Cycles reaches with the headline rung's
    samples, ending with penumbra's time over Cycles'; then the details."""
    w, h = results["resolution"]
    hr = results["headline_rung"]
    lines = ["# Time to equal RMSE: penumbra against Cycles", "",
             f"Measured {results['date']} on {results['machine']}; load average {results['load_before']} "
             f"before, {results.get('load_after')} after; {results.get('total_seconds', 0) / 60:.0f} minutes. "
             f"Blender {next(iter(results['scenes'].values()))['cycles_settings'].get('blender', '?')}.", "",
             f"Command: `{results['command']}`", "",
             f"{w}x{h}, {results['threads']} threads for both, ladder {results['ladder']} spp, {results['reps']} "
             f"repetitions of each rung (the renderers alternating), references 2 x {results['reference_spp'] // 2} "
             f"spp per renderer; penumbra adaptive at --min-spp {results['min_spp']}, with the relative criterion "
             "(the default, for display) and with the absolute one (`--adaptive-error absolute`: the image's "
             "RMSE as its target, samples where the noise is). Times: penumbra's whole "
             "process; Cycles' render call inside Blender. RMSE against each renderer's own reference, the "
             "reference's own noise subtracted.", "",
             f"At the RMSE Cycles reaches with {hr} spp (medians of the repetitions; penumbra's time "
             "interpolated on its log-log curve of RMSE against time; CPU: the same with CPU time, user + "
             "system of all threads):", "",
             "| scene | references agree (means; 8x8 blocks within noise or 1%) | RMSE | Cycles s | "
             "penumbra adaptive s | adaptive / Cycles | adaptive (image RMSE) s | adaptive (image RMSE) / Cycles | "
             "CPU time: penumbra / Cycles | penumbra s | penumbra / Cycles |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in results["scenes"].items():
        a = r["agreement"]
        agree = (f"{'yes' if a['agree'] else 'NO'} ({100 * a['mean_rel_diff']:+.2f}%; "
                 f"{100 * a['blocks_within_3se_or_1pct']:.0f}%)")
        row = next((x for x in r["equal_error"] if x["spp"] == hr), None)
        if row is None:
            lines.append(f"| {name} | {agree} | - | - | - | - | - | - | - | - | - |")
            continue
        lines.append(f"| {name} | {agree} | {row['rmse']:.4g} | {row['cycles_seconds']:.2f} | "
                     f"{fmt_s(row['penumbra_adaptive_seconds'])} | {fmt_ratio(row['penumbra_adaptive_ratio'])} | "
                     f"{fmt_s(row.get('penumbra_adaptive_rmse_seconds'))} | "
                     f"{fmt_ratio(row.get('penumbra_adaptive_rmse_ratio'))} | "
                     f"{fmt_ratio(row['penumbra_cpu_ratio'])} | "
                     f"{fmt_s(row['penumbra_seconds'])} | {fmt_ratio(row['penumbra_ratio'])} |")
    ladder_head = ["| scene | " + " | ".join(f"{n} spp" for n in results["ladder"]) + " |",
                   "|---|" + "---|" * len(results["ladder"])]
    lines += ["", "penumbra / Cycles at every Cycles rung's RMSE, wall time (CPU time); `-`: outside "
              "penumbra's curve:", ""] + ladder_head
    for name, r in results["scenes"].items():
        lines.append(f"| {name} | " + " | ".join(
            f"{fmt_ratio(x['penumbra_ratio'])} ({fmt_ratio(x['penumbra_cpu_ratio'])})" for x in r["equal_error"]) + " |")
    lines += ["", "penumbra adaptive (image RMSE) / Cycles at every Cycles rung's RMSE, wall time (CPU time):", ""]
    lines += ladder_head
    for name, r in results["scenes"].items():
        lines.append(f"| {name} | " + " | ".join(
            f"{fmt_ratio(x.get('penumbra_adaptive_rmse_ratio'))} ({fmt_ratio(x.get('penumbra_adaptive_rmse_cpu_ratio'))})"
            for x in r["equal_error"]) + " |")
    for key, what in (("adaptive_vs_fixed", "penumbra adaptive"),
                      ("adaptive_rmse_vs_fixed", "penumbra adaptive (image RMSE)")):
        lines += ["", f"{what} against penumbra fixed, at each fixed rung's RMSE: time, wall (CPU), and "
                  "mean samples per pixel, as a ratio to the fixed render's:", ""] + ladder_head
        for name, r in results["scenes"].items():
            lines.append(f"| {name} | " + " | ".join(
                f"{fmt_ratio(x['ratio'])} ({fmt_ratio(x['cpu_ratio'])}), spp {fmt_ratio(x['spp_ratio'])}"
                if x["ratio"] or x["spp_ratio"] else "-" for x in r.get(key, [])) + " |")
    for name, r in results["scenes"].items():
        a = r["agreement"]
        lines += ["", f"## {name}", "", r["what"] + ".", "",
                  f"![RMSE against wall time, {name}](time-to-error-{name}.png)", "",
                  f"References: means {a['mean_penumbra']:.5g} (penumbra) and {a['mean_cycles']:.5g} (Cycles), "
                  f"{100 * a['mean_rel_diff']:+.2f}% (R, G, B: "
                  + ", ".join(f"{100 * v:+.2f}%" for v in a["channel_rel_diff"])
                  + f"); of the 8x8 blocks, {100 * a['blocks_within_3se']:.1f}% within 3 standard errors, "
                  f"{100 * a['blocks_within_3se_or_1pct']:.1f}% within that or 1%; mean z^2 {a['mean_z2']:.2f}. "
                  f"Their own noise (RMSE against the converged image, from the halves): "
                  f"{r['reference_noise_rmse']['penumbra']:.3g} and {r['reference_noise_rmse']['cycles']:.3g}; "
                  f"rendered in {r['reference_seconds']['penumbra']:.0f} s and {r['reference_seconds']['cycles']:.0f} s "
                  f"of wall time.", ""]
        if a.get("bokeh"):
            pairs = list(zip(a["bokeh"]["penumbra"], a["bokeh"]["cycles"]))
            lines += ["Bokeh spots of the references (bokeh_spots), penumbra / Cycles: RMS radius in pixels "
                      + ", ".join(f"{p['rms_radius']:.2f} / {c['rms_radius']:.2f}" for p, c in pairs)
                      + "; energy " + ", ".join(f"{p['energy']:.1f} / {c['energy']:.1f}" for p, c in pairs)
                      + "; hexagon orientation (degrees, modulo 60) "
                      + ", ".join(f"{p['phase_deg']:.1f} / {c['phase_deg']:.1f}" for p, c in pairs) + ".", ""]
        lines += ["| spp | penumbra s (reps) | CPU s | RMSE | Cycles s (reps) | CPU s | RMSE | adaptive threshold | "
                  "adaptive mean spp | adaptive s (reps) | RMSE | image RMSE target | mean spp | adaptive (image "
                  "RMSE) s (reps) | RMSE |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        adaptive = {x["key"]: x for x in r["curves"]["penumbra adaptive"]}
        adaptive_rmse = {x["key"]: x for x in r["curves"].get("penumbra adaptive rmse", [])}
        reps = lambda e: ", ".join(f"{v:.2f}" for v in e["seconds_all"])
        for p, c in zip(r["curves"]["penumbra"], r["curves"]["cycles"]):
            ad, ar = adaptive.get(p["key"]), adaptive_rmse.get(p["key"])
            lines.append(f"| {p['key']} | {p['seconds']:.2f} ({reps(p)}) | {p.get('cpu_seconds', 0):.2f} | "
                         f"{p['rmse']:.4g} | {c['seconds']:.2f} ({reps(c)}) | {c.get('cpu_seconds', 0):.2f} | "
                         f"{c['rmse']:.4g} | "
                         + (f"{ad['threshold']:.4g} | {ad.get('mean_spp', 0):.1f} | {ad['seconds']:.2f} ({reps(ad)}) | "
                            f"{ad['rmse']:.4g} |" if ad else "- | - | - | - |")
                         + (f" {ar['threshold']:.4g} | {ar.get('mean_spp', 0):.1f} | {ar['seconds']:.2f} ({reps(ar)}) | "
                            f"{ar['rmse']:.4g} |" if ar else " - | - | - | - |"))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
