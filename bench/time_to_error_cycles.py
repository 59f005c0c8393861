"""Builds one scene of bench/time_to_error.py in Blender and renders it with Cycles:

    blender -b --factory-startup --python bench/time_to_error_cycles.py -- SPEC.json

SPEC.json holds the scene's description (`SCENES` in time_to_error.py, penumbra's y-up
coordinates), spp, seed, threads, width, height and the output EXR. The render call is timed here
(wall and CPU time of the process, printed as CYCLES_RENDER_SECONDS), so that Blender's start-up
is not; the settings used are printed as CYCLES_SETTINGS. time_to_error.py's docstring lists
every difference from the penumbra scene.
"""
import json, math, os, sys, time
import bpy, mathutils

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_scene import new_cycles_scene  # noqa: E402

spec = json.load(open(sys.argv[sys.argv.index("--") + 1]))
scene_desc = spec["scene"]

def to_blender(p):  # penumbra's y-up coordinates to Blender's z-up: rotate about x by 90 degrees
    return (p[0], -p[2], p[1])

# penumbra's max_depth counts the vertices that scatter (1: direct light only); Cycles' bounces
# count the scatterings after the first (0: direct light only), so it gets max_depth - 1. Volume
# scatterings count as bounces in both.
scene = new_cycles_scene(spec["spp"], spec["seed"], spec["threads"], spec["width"], spec["height"],
                         scene_desc["depth"] - 1, (0.0, 0.0, 0.0))
cy = scene.cycles

# How Cycles samples distances in the homogeneous media (penumbra: delta tracking, which for a
# homogeneous medium is distance sampling): multiple importance sampling of distance and
# equiangular sampling (Blender's default), the robust choice for a small light inside a fog.
VOLUME_SAMPLING = spec.get("volume_sampling", "MULTIPLE_IMPORTANCE")

def rgb(v):
    return list(v) if isinstance(v, list) else [v] * 3

def medium_material(name, medium):
    """A pure volume boundary: a material with only a Volume output (no surface shader: rays pass
    through it without a bounce), the medium inside. sigma_s = Volume Scatter's Color x Density,
    sigma_a = (1 - Volume Absorption's Color) x Density (Cycles' svm_node_closure_volume), per
    scene unit as penumbra's."""
    desc = scene_desc["media"][medium]
    assert desc["type"] == "homogeneous" and not desc.get("emission"), desc
    scale = desc.get("scale", 1.0)
    sigma_a = [scale * v for v in rgb(desc.get("sigma_a", 0.0))]
    sigma_s = [scale * v for v in rgb(desc.get("sigma_s", 0.0))]
    m = bpy.data.materials.new(f"{name}-{medium}")
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    scatter = nodes.new("ShaderNodeVolumeScatter")
    density_s = max(sigma_s) or 1.0
    scatter.inputs["Color"].default_value = (*[v / density_s for v in sigma_s], 1)
    scatter.inputs["Density"].default_value = density_s if max(sigma_s) > 0 else 0.0
    scatter.inputs["Anisotropy"].default_value = desc.get("g", 0.0)
    absorb = nodes.new("ShaderNodeVolumeAbsorption")
    density_a = max(sigma_a) or 1.0
    absorb.inputs["Color"].default_value = (*[1 - v / density_a for v in sigma_a], 1)
    absorb.inputs["Density"].default_value = density_a if max(sigma_a) > 0 else 0.0
    add = nodes.new("ShaderNodeAddShader")
    links.new(scatter.outputs[0], add.inputs[0])
    links.new(absorb.outputs[0], add.inputs[1])
    links.new(add.outputs[0], out.inputs["Volume"])
    # Homogeneous: one step over the whole segment, transmittance in closed form (the shader has no
    # spatially varying input, so Cycles would find this itself; said here for certain).
    m.cycles.homogeneous_volume = True
    m.cycles.volume_sampling = VOLUME_SAMPLING
    return m

materials = {}
def material(name, emission=None, inside=None, outside=None):
    key = (name, tuple(emission) if emission else None, inside)
    if key in materials:
        return materials[key]
    desc = scene_desc["materials"][name]
    if desc["type"] == "interface":
        # Cycles' media are the insides of closed meshes, the vacuum around them.
        assert inside and not outside and not emission, (name, inside, outside)
        materials[key] = medium_material(name, inside)
        return materials[key]
    assert not inside and not outside, "media behind a surface that scatters: not described for Cycles"
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
    mat = material(s["material"], s.get("emission"), s.get("inside"), s.get("outside"))
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
    # penumbra's rotation puts a corner on +x, Cycles' an edge's midpoint (see the scene): the scene
    # gives penumbra's angle, with the offset of 180/blades degrees already in it.
    blades = cam_desc.get("aperture_blades", 0)
    if blades:
        cam_data.dof.aperture_rotation = math.radians(cam_desc.get("aperture_rotation", 0) - 180.0 / blades)
scene.render.use_motion_blur = moving
if moving:
    scene.render.motion_blur_shutter = 1.0
    cy.motion_blur_position = "START"
scene.frame_set(1)

start, cpu_start = time.perf_counter(), time.process_time()
bpy.ops.render.render()
seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu_start
bpy.data.images["Render Result"].save_render(spec["output"])
print("CYCLES_RENDER_SECONDS", seconds, cpu_seconds, flush=True)
print("CYCLES_SETTINGS", json.dumps({"blender": bpy.app.version_string, "sampling_pattern": cy.sampling_pattern,
      "light_sampling_threshold": cy.light_sampling_threshold, "threads": scene.render.threads,
      "max_bounces": cy.max_bounces, "volume_bounces": cy.volume_bounces,
      "volume_sampling": VOLUME_SAMPLING if scene_desc.get("media") else None,
      "homogeneous_volume": True if scene_desc.get("media") else None,
      "lens_mm": cam_data.lens, "fstop": cam_data.dof.aperture_fstop if cam_data.dof.use_dof else None}), flush=True)
