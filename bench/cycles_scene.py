"""What every Cycles render of the benchmarks shares (bench/time_to_error_cycles.py,
bench/subsurface_cycles.py), run inside Blender: an empty scene rendered by Cycles on the CPU at a
fixed sample count and seed, without adaptive sampling, denoising, clamping or glossy blur, with
caustics, a 1-pixel box filter, the Standard view and 32-bit float EXR output, on a fixed number of
threads; `bounces` for every kind of bounce, volume scatterings included.
"""
import bpy


def new_cycles_scene(spp, seed, threads, width, height, bounces, world_color):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = spp
    cy.use_adaptive_sampling = False
    cy.seed = seed
    cy.use_denoising = False
    cy.max_bounces = cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = bounces
    cy.transparent_max_bounces = bounces
    # volume_bounces (default 0: single scattering only) must not cut volume scatterings first.
    cy.volume_bounces = bounces
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = cy.caustics_refractive = True
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    world = bpy.data.worlds.new("world")
    world.use_nodes = False
    world.color = world_color
    scene.world = world
    return scene
