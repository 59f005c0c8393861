#!/usr/bin/python3
"""Time to a clean image: penumbra (fixed and adaptive sampling) against Blender's Cycles, at equal
RMSE, on four scenes that exercise distribution effects. Run with Debian's Python (python3-numpy,
python3-openimageio, python3-matplotlib) and Debian's `blender` (3.4; scripts/install-deps.sh
bench installs it):

    /usr/bin/python3 bench/time_to_error.py [--penumbra build/tools/penumbra] [--threads 2]
        [--res 320x240] [--ladder 4,8,...,256] [--reference-spp 4096] [--scenes dof,...] [-o DIR]

For each scene (`SCENES` below: depth of field with bokeh, two area lights with wide penumbrae,
motion blur of a rotating and a translating object, a glass sphere with a caustic under an area
light), one description is written out twice: as a penumbra scene file and as a Blender Python
script that builds the same scene for Cycles. Then, per scene:
  1. a reference at --reference-spp with each renderer; the two must agree (image means within
     1%, and 16x16-pixel block means within 5 standard errors of their difference in at least
     95% of the blocks), or the scene is reported as not comparable;
  2. each renderer at every rung of --ladder, alternating penumbra and Cycles, with the same
     thread count; penumbra also adaptive, at --adaptive thresholds (same ladder as maximum);
  3. the RMSE of each image against its own renderer's reference; the wall time each renderer
     needs to reach the same RMSE, interpolated on the log-log curve of RMSE against time.
penumbra's time is the wall time of the whole `penumbra render` process (start-up, scene load,
BVH build, render and writing the EXR); Cycles' is the render call inside Blender
(`bpy.ops.render.render`, timed in the script: scene sync, BVH build and render; Blender's own
start-up is left out).

What the two scenes share, and where they differ (the closest Cycles equivalents):
  - camera: same position, look-at and vertical field of view (sensor fit vertical); thin lens of
    the same aperture radius and focus distance; polygonal apertures have the same blade count
    (the blades' rotation conventions may differ by a constant angle);
  - film: box filter one pixel wide in both (penumbra `box` radius 0.5, Cycles BOX width 1);
  - path depth: penumbra max_depth = Cycles max_bounces (and each of its diffuse, glossy and
    transmission limits); Cycles' light tree / MIS and Russian roulette are its own; clamping,
    filter glossy and denoising are off in Cycles, caustics on;
  - materials: Lambert = Diffuse BSDF (roughness 0); dielectric = Glass BSDF, sharp, same IOR;
    emitters are two-sided in both (Cycles' mesh lights always are);
  - spheres: analytic in penumbra, UV spheres of 128 x 64 faces with smooth normals in Cycles;
  - motion: penumbra's shutter [0, 1] with transform keys at its ends; Cycles' shutter of one
    frame starting at frame 1, with linear keyframes at frames 1 and 2 (9 motion steps).
Coordinates are penumbra's (y up); Blender gets them rotated about x by 90 degrees (z up).

Writes DIR/time-to-error.json, DIR/time-to-error.md (one row per scene, ending with the ratio
written like `0.42x`) and DIR/time-to-error-SCENE.png (RMSE against time, both renderers).
"""

import argparse
import json
import math
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


def box(center, half, material, spin_degrees=None):
    """An axis-aligned box; spin_degrees: [at open, at close] rotation about +y, about its centre."""
    return {"kind": "box", "center": center, "half": half, "material": material, "spin": spin_degrees}


FLOOR = quad([-8, 0, 8], [16, 0, 0], [0, 0, -16], "floor")
BASE_MATERIALS = {"floor": {"type": "lambert", "albedo": 0.6}, "black": {"type": "lambert", "albedo": 0.0}}

SCENES = {
    "dof": {
        "what": "depth of field: spheres at several depths, small bright spheres behind the focus (hexagonal bokeh)",
        "camera": {"look_from": [0, 1.0, 6], "look_at": [0, 0.5, 0], "fov": 35, "aperture_radius": 0.12,
                   "aperture_blades": 6, "focus_distance": 6.0},
        "depth": 6,
        "materials": {**BASE_MATERIALS, "red": {"type": "lambert", "albedo": [0.75, 0.2, 0.15]},
                      "blue": {"type": "lambert", "albedo": [0.15, 0.3, 0.75]}},
        "shapes": [FLOOR, sphere([-1.2, 0.5, 2.5], 0.5, "red"), sphere([0.2, 0.5, 0.0], 0.5, "blue"),
                   sphere([1.5, 0.5, -3.0], 0.5, "red")]
                  + [sphere([-3 + 1.2 * i, 1.6 + 0.3 * (i % 2), -7], 0.06, "black", emission=[60, 50, 40])
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
            if s.get("spin"):
                shape["motion"] = {"transforms": [{"rotate": {"axis": [0, 1, 0], "degrees": d},
                                                   "translate": s["center"]} for d in s["spin"]]}
            shapes.append(shape)
    return {"camera": scene["camera"],
            "film": {"resolution": [width, height], "spp": spp, "filter": {"type": "box", "radius": 0.5}},
            "integrator": {"max_depth": scene["depth"]},
            "materials": scene["materials"], "shapes": shapes}


# ---------------------------------------------------------------------------------------------
# Blender: a script run with `blender -b --factory-startup --python SCRIPT -- SPEC.json`, which
# builds the scene, renders it with Cycles, times the render call and writes the EXR.

BLENDER_SCRIPT = r'''
import json, math, sys, time
import bpy, mathutils

spec = json.load(open(sys.argv[sys.argv.index("--") + 1]))
scene_desc = spec["scene"]

def to_blender(p):  # penumbra's y-up coordinates to Blender's z-up: rotate about x by 90 degrees
    return (p[0], -p[2], p[1])

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"
cy.samples = spec["spp"]
cy.use_adaptive_sampling = False
cy.seed = spec["seed"]
cy.use_denoising = False
cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = scene_desc["depth"]
cy.transparent_max_bounces = scene_desc["depth"]
cy.volume_bounces = 0
cy.sample_clamp_direct = 0.0
cy.sample_clamp_indirect = 0.0
cy.blur_glossy = 0.0
cy.caustics_reflective = cy.caustics_refractive = True
cy.pixel_filter_type = "BOX"
cy.filter_width = 1.0
scene.render.threads_mode = "FIXED"
scene.render.threads = spec["threads"]
scene.render.resolution_x, scene.render.resolution_y = spec["width"], spec["height"]
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
world = bpy.data.worlds.new("world")
world.use_nodes = False
world.color = (0.0, 0.0, 0.0)
scene.world = world

materials = {}
def material(name, emission=None):
    key = (name, tuple(emission) if emission else None)
    if key in materials:
        return materials[key]
    desc = scene_desc["materials"][name]
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    if desc["type"] == "dielectric":
        bsdf = nodes.new("ShaderNodeBsdfGlass")
        bsdf.distribution = "SHARP"
        bsdf.inputs["IOR"].default_value = desc["eta"]
        bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
    else:
        albedo = desc.get("albedo", 0.5)
        albedo = albedo if isinstance(albedo, list) else [albedo] * 3
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = (*albedo, 1)
        bsdf.inputs["Roughness"].default_value = 0.0
    shader = bsdf
    if emission:
        glow = nodes.new("ShaderNodeEmission")
        glow.inputs["Color"].default_value = (*emission, 1)
        glow.inputs["Strength"].default_value = 1.0
        add = nodes.new("ShaderNodeAddShader")
        links.new(bsdf.outputs[0], add.inputs[0])
        links.new(glow.outputs[0], add.inputs[1])
        shader = add
    links.new(shader.outputs[0], out.inputs["Surface"])
    materials[key] = m
    return m

def add_mesh(name, positions, faces, mat, smooth=False):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([to_blender(p) for p in positions], [], faces)
    mesh.update()
    for poly in mesh.polygons:
        poly.use_smooth = smooth
    obj = bpy.data.objects.new(name, mesh)
    obj.data.materials.append(mat)
    scene.collection.objects.link(obj)
    return obj

def linear_keys(obj, path, values):
    for frame, value in zip((1, 2), values):
        setattr(obj, path, value)
        obj.keyframe_insert(path, frame=frame)
    for curve in obj.animation_data.action.fcurves:
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"

def uv_sphere(radius, segments=128, rings=64):
    positions, faces = [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            positions.append([radius * math.sin(theta) * math.cos(phi), radius * math.cos(theta),
                              -radius * math.sin(theta) * math.sin(phi)])
    for r in range(rings):
        for s in range(segments):
            a, b = r * segments + s, r * segments + (s + 1) % segments
            faces.append([a, a + segments, b + segments, b])
    return positions, faces

moving = False
for i, s in enumerate(scene_desc["shapes"]):
    mat = material(s["material"], s.get("emission"))
    if s["kind"] == "quad":
        c, e1, e2 = s["corner"], s["edge1"], s["edge2"]
        corners = [c, [c[k] + e1[k] for k in range(3)], [c[k] + e1[k] + e2[k] for k in range(3)],
                   [c[k] + e2[k] for k in range(3)]]
        add_mesh(f"quad{i}", corners, [[0, 1, 2, 3]], mat)
    elif s["kind"] == "sphere":
        positions, faces = uv_sphere(s["radius"])
        obj = add_mesh(f"sphere{i}", positions, faces, mat, smooth=True)
        if s.get("motion"):
            moving = True
            linear_keys(obj, "location", [to_blender(t) for t in s["motion"]])
        else:
            obj.location = to_blender(s["center"])
    elif s["kind"] == "box":
        cx, cy_, cz = (0, 0, 0) if s.get("spin") else s["center"]
        hx, hy, hz = s["half"]
        positions = [[cx + sx * hx, cy_ + sy * hy, cz + sz * hz] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
        faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
        obj = add_mesh(f"box{i}", positions, faces, mat)
        if s.get("spin"):
            moving = True
            obj.location = to_blender(s["center"])
            # penumbra's +y is Blender's +z.
            linear_keys(obj, "rotation_euler", [(0.0, 0.0, math.radians(d)) for d in s["spin"]])
        if moving:
            obj.cycles.motion_steps = 4

cam_desc = scene_desc["camera"]
cam_data = bpy.data.cameras.new("camera")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(cam_desc["fov"])
cam = bpy.data.objects.new("camera", cam_data)
scene.collection.objects.link(cam)
scene.camera = cam
eye, target = mathutils.Vector(to_blender(cam_desc["look_from"])), mathutils.Vector(to_blender(cam_desc["look_at"]))
cam.location = eye
cam.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
if cam_desc.get("aperture_radius"):
    cam_data.dof.use_dof = True
    cam_data.dof.focus_distance = cam_desc.get("focus_distance", (target - eye).length)
    # Cycles' aperture radius is lens * 1e-3 / (2 f-stop), the lens in mm (scene units in metres).
    cam_data.dof.aperture_fstop = cam_data.lens * 1e-3 / (2 * cam_desc["aperture_radius"])
    cam_data.dof.aperture_blades = cam_desc.get("aperture_blades", 0)
scene.render.use_motion_blur = moving
if moving:
    scene.render.motion_blur_shutter = 1.0
    cy.motion_blur_position = "START"
scene.frame_set(1)

start = time.perf_counter()
bpy.ops.render.render()
seconds = time.perf_counter() - start
bpy.data.images["Render Result"].save_render(spec["output"])
print("CYCLES_RENDER_SECONDS", seconds, flush=True)
'''


# ---------------------------------------------------------------------------------------------
# Running the renderers.

def read_rgb(path):
    image = oiio.ImageInput.open(path)
    if image is None:
        raise SystemExit(f"cannot read {path}: {oiio.geterror()}")
    spec = image.spec()
    pixels = image.read_image(0, 0, 0, 3, "float")
    image.close()
    return np.asarray(pixels, dtype=np.float64).reshape(spec.height, spec.width, 3)


def run_penumbra(binary, scene_file, out, threads, spp, seed, adaptive=None):
    cmd = [binary, "render", scene_file, "--spp", str(spp), "--seed", str(seed), "--threads", str(threads),
           "--no-display", "-q", "-o", out]
    if adaptive:
        cmd += ["--adaptive", str(adaptive)]
    start = time.perf_counter()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"penumbra failed: {' '.join(cmd)}\n{proc.stderr}")
    return seconds


def run_cycles(blender, script, spec_file, spec):
    with open(spec_file, "w") as f:
        json.dump(spec, f)
    cmd = [blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script, "--", spec_file]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = None
    for line in proc.stdout.splitlines():
        if line.startswith("CYCLES_RENDER_SECONDS"):
            seconds = float(line.split()[1])
    if proc.returncode != 0 or seconds is None or not os.path.exists(spec["output"]):
        raise SystemExit(f"blender failed: {' '.join(cmd)}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return seconds


def rmse(image, reference):
    return float(np.sqrt(np.mean((image - reference) ** 2)))


def references_agree(a, b, block=16):
    """Means within 1%; 16x16 block means within 5 standard errors of their difference (the spread
    of the block differences estimates it) in at least 95% of the blocks."""
    mean_a, mean_b = float(a.mean()), float(b.mean())
    mean_ok = abs(mean_a - mean_b) <= 0.01 * max(abs(mean_b), 1e-12)
    h, w = (a.shape[0] // block) * block, (a.shape[1] // block) * block
    blocks = lambda img: img[:h, :w].reshape(h // block, block, w // block, block, 3).mean(axis=(1, 3))
    diff = blocks(a) - blocks(b)
    spread = float(np.std(diff)) or 1e-12
    within = float(np.mean(np.abs(diff - diff.mean()) <= 5 * spread))
    return {"mean_penumbra": mean_a, "mean_cycles": mean_b, "mean_ok": mean_ok, "blocks_within": within,
            "agree": bool(mean_ok and within >= 0.95)}


def time_at_rmse(points, target):
    """Seconds at `target` RMSE on the log-log curve through (seconds, rmse) points; None outside."""
    pts = sorted(points, key=lambda p: p[1])
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if min(e0, e1) <= target <= max(e0, e1) and e0 > 0 and e1 > 0 and t0 > 0 and t1 > 0:
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--penumbra", default=os.path.join(REPO, "build", "tools", "penumbra"))
    parser.add_argument("--blender", default=shutil.which("blender") or "blender")
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    parser.add_argument("--res", default="320x240")
    parser.add_argument("--ladder", default="4,8,...,256")
    parser.add_argument("--adaptive", default="0.2,0.1,0.05,0.025,0.0125",
                        help="penumbra's adaptive thresholds (maximum spp: the top rung)")
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("-o", "--output", default=os.path.join(REPO, "bench", "results"))
    args = parser.parse_args()
    width, height = (int(v) for v in args.res.split("x"))
    ladder = parse_ladder(args.ladder)
    thresholds = [float(t) for t in args.adaptive.split(",") if t]
    os.makedirs(args.output, exist_ok=True)
    work = tempfile.mkdtemp(prefix="penumbra-time-to-error-")
    script = os.path.join(work, "cycles_scene.py")
    with open(script, "w") as f:
        f.write(BLENDER_SCRIPT)

    results = {"resolution": [width, height], "threads": args.threads, "ladder": ladder,
               "reference_spp": args.reference_spp, "thresholds": thresholds, "scenes": {}}
    for name in args.scenes.split(","):
        scene = SCENES[name]
        log(f"{name}: {scene['what']}")
        scene_file = os.path.join(work, f"{name}.json")
        with open(scene_file, "w") as f:
            json.dump(penumbra_scene(scene, width, height, args.reference_spp), f, indent=1)
        spec_file = os.path.join(work, f"{name}-cycles.json")

        def cycles(spp, seed, out):
            return run_cycles(args.blender, script, spec_file,
                              {"scene": scene, "spp": spp, "seed": seed, "threads": args.threads, "width": width,
                               "height": height, "output": out})

        ref_p, ref_c = os.path.join(work, f"{name}-ref-penumbra.exr"), os.path.join(work, f"{name}-ref-cycles.exr")
        log(f"  references at {args.reference_spp} spp")
        run_penumbra(args.penumbra, scene_file, ref_p, args.threads, args.reference_spp, 1000)
        cycles(args.reference_spp, 1000, ref_c)
        reference = {"penumbra": read_rgb(ref_p), "cycles": read_rgb(ref_c)}
        agreement = references_agree(reference["penumbra"], reference["cycles"])
        log(f"  references: means {agreement['mean_penumbra']:.5g} and {agreement['mean_cycles']:.5g}, "
            f"{100 * agreement['blocks_within']:.1f}% of blocks within noise: "
            f"{'agree' if agreement['agree'] else 'DO NOT AGREE'}")

        curves = {"penumbra": [], "penumbra adaptive": [], "cycles": []}
        for spp in ladder:  # alternating, the same thread count
            out = os.path.join(work, f"{name}-p-{spp}.exr")
            seconds = run_penumbra(args.penumbra, scene_file, out, args.threads, spp, 1)
            curves["penumbra"].append({"spp": spp, "seconds": seconds, "rmse": rmse(read_rgb(out), reference["penumbra"])})
            out = os.path.join(work, f"{name}-c-{spp}.exr")
            seconds = cycles(spp, 1, out)
            curves["cycles"].append({"spp": spp, "seconds": seconds, "rmse": rmse(read_rgb(out), reference["cycles"])})
            log(f"  {spp:5d} spp: penumbra {curves['penumbra'][-1]['seconds']:.2f} s RMSE "
                f"{curves['penumbra'][-1]['rmse']:.4g}, cycles {seconds:.2f} s RMSE {curves['cycles'][-1]['rmse']:.4g}")
        for threshold in thresholds:
            out = os.path.join(work, f"{name}-a-{threshold}.exr")
            seconds = run_penumbra(args.penumbra, scene_file, out, args.threads, ladder[-1], 1, adaptive=threshold)
            curves["penumbra adaptive"].append({"threshold": threshold, "seconds": seconds,
                                                "rmse": rmse(read_rgb(out), reference["penumbra"])})
            log(f"  adaptive {threshold}: {seconds:.2f} s RMSE {curves['penumbra adaptive'][-1]['rmse']:.4g}")

        # Equal error: the Cycles rungs' RMSEs, reached by penumbra (fixed, adaptive) in how long.
        rows = []
        for c in curves["cycles"]:
            row = {"rmse": c["rmse"], "cycles_seconds": c["seconds"]}
            for kind in ("penumbra", "penumbra adaptive"):
                t = time_at_rmse([(p["seconds"], p["rmse"]) for p in curves[kind]], c["rmse"])
                row[kind.replace(" ", "_") + "_seconds"] = t
                row[kind.replace(" ", "_") + "_ratio"] = t / c["seconds"] if t else None
            rows.append(row)
        results["scenes"][name] = {"what": scene["what"], "agreement": agreement, "curves": curves, "equal_error": rows}
        plot(name, curves, os.path.join(args.output, f"time-to-error-{name}.png"))

    with open(os.path.join(args.output, "time-to-error.json"), "w") as f:
        json.dump(results, f, indent=1)
    write_table(results, os.path.join(args.output, "time-to-error.md"))
    shutil.rmtree(work, ignore_errors=True)
    return 0


def plot(name, curves, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for kind, style in (("penumbra", "o-"), ("penumbra adaptive", "s-."), ("cycles", "^--")):
        pts = sorted(curves[kind], key=lambda p: p["seconds"])
        ax.plot([p["seconds"] for p in pts], [p["rmse"] for p in pts], style, label=kind, ms=4)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("RMSE against the renderer's own reference")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(name, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_table(results, path):
    """One row per scene, at the RMSE of Cycles' middle rung that both penumbra curves reach."""
    lines = ["# Time to equal RMSE: penumbra against Cycles", "",
             f"{results['resolution'][0]}x{results['resolution'][1]}, {results['threads']} threads, ladder "
             f"{results['ladder']}, references at {results['reference_spp']} spp.", "",
             "| scene | references agree | RMSE | Cycles s | penumbra s | adaptive s | penumbra / Cycles | adaptive / Cycles |",
             "|---|---|---|---|---|---|---|---|"]
    for name, r in results["scenes"].items():
        rows = [row for row in r["equal_error"] if row["penumbra_seconds"] and row["penumbra_adaptive_seconds"]]
        row = rows[len(rows) // 2] if rows else None
        agree = "yes" if r["agreement"]["agree"] else "no"
        if row is None:
            lines.append(f"| {name} | {agree} | - | - | - | - | - | - |")
            continue
        lines.append(f"| {name} | {agree} | {row['rmse']:.4g} | {row['cycles_seconds']:.2f} | "
                     f"{row['penumbra_seconds']:.2f} | {row['penumbra_adaptive_seconds']:.2f} | "
                     f"{row['penumbra_ratio']:.2f}x | {row['penumbra_adaptive_ratio']:.2f}x |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
