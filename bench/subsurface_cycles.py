"""The slab of bench/subsurface_peers.py in Blender, rendered with Cycles' random-walk subsurface:

    blender -b --factory-startup --python bench/subsurface_cycles.py -- SPEC.json

SPEC.json: color (the subsurface colour, Cycles' albedo), radius (per channel, scene units),
ior, falloff (RANDOM_WALK or RANDOM_WALK_FIXED_RADIUS), spp, seed, threads, size, output (EXR).
The slab: a box 200 x 200 wide and 100 deep whose top face is z = 0, seen straight down by an
orthographic camera 2 units wide, under a uniform world of radiance 1; no other object.
"""
import json, os, sys
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_scene import new_cycles_scene  # noqa: E402

spec = json.load(open(sys.argv[sys.argv.index("--") + 1]))

scene = new_cycles_scene(spec["spp"], spec["seed"], spec["threads"], spec["size"], spec["size"], 64,
                         (1.0, 1.0, 1.0))

material = bpy.data.materials.new("slab")
material.use_nodes = True
nodes, links = material.node_tree.nodes, material.node_tree.links
nodes.clear()
out = nodes.new("ShaderNodeOutputMaterial")
sss = nodes.new("ShaderNodeSubsurfaceScattering")
sss.falloff = spec["falloff"]
sss.inputs["Color"].default_value = (*spec["color"], 1)
sss.inputs["Scale"].default_value = 1.0
sss.inputs["Radius"].default_value = spec["radius"]
sss.inputs["IOR"].default_value = spec["ior"]
sss.inputs["Anisotropy"].default_value = 0.0
links.new(sss.outputs[0], out.inputs["Surface"])

lo, hi = (-100.0, -100.0, -100.0), (100.0, 100.0, 0.0)
corners = [(hi[0] if v & 1 else lo[0], hi[1] if v & 2 else lo[1], hi[2] if v & 4 else lo[2]) for v in range(8)]
faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]  # outward
mesh = bpy.data.meshes.new("slab")
mesh.from_pydata(corners, [], faces)
mesh.materials.append(material)
slab = bpy.data.objects.new("slab", mesh)
scene.collection.objects.link(slab)

camera_data = bpy.data.cameras.new("camera")
camera_data.type = "ORTHO"
camera_data.ortho_scale = 2.0
camera_data.clip_end = 1000.0
camera = bpy.data.objects.new("camera", camera_data)
camera.location = (0.0, 0.0, 5.0)  # looking down -z, the default orientation
scene.collection.objects.link(camera)
scene.camera = camera

scene.render.filepath = spec["output"]
bpy.ops.render.render(write_still=True)
