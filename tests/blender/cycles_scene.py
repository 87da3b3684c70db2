"""Renders a hair scene described by a JSON file with Cycles, headless (the Cycles cross-check of
tests/python/test_cycles_crosscheck.py; not a pytest module).

blender -b --factory-startup --python tests/blender/cycles_scene.py -- SCENE.json OUT.exr

SCENE.json: {"addon": folder holding hairlod, "hair": hair file, "camera": {eye, target, up, fov_y,
width, height}, "sun": {"direction": the way light travels, "irradiance"}, "world": grey radiance,
"node": Principled Hair BSDF inputs in hairlod.hair_params.from_principled_hair's names, "spp", "seed",
"max_bounces"}. Writes linear float RGB(A) OpenEXR.
"""

import json
import sys

import bpy
import numpy as np
from mathutils import Matrix, Vector


def main():
    scene_path, out_path = sys.argv[sys.argv.index("--") + 1:][:2]
    with open(scene_path) as f:
        spec = json.load(f)
    sys.path.insert(0, spec["addon"])
    from hairlod import io
    from hairlod.blender.curves import strands_to_curves
    from hairlod.blender.principled_hair import new_hair_material
    from hairlod.camera import look_at

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    hair = strands_to_curves(io.read(spec["hair"]), "Hair", scene.collection)

    material = new_hair_material("Hair", {**spec["node"], "random_color": 0.0, "random_roughness": 0.0, "random": 0.0})
    hair.data.materials.append(material)

    camera = spec["camera"]
    data = bpy.data.cameras.new("Camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = camera["fov_y"]
    distance = float(np.linalg.norm(np.subtract(camera["eye"], camera["target"])))
    data.clip_start, data.clip_end = 1e-3 * distance, 1e3 * distance
    camera_object = bpy.data.objects.new("Camera", data)
    # hairlod.camera.look_at is world-to-camera in Blender's convention (camera looks down -z, y up).
    camera_object.matrix_world = Matrix(np.linalg.inv(look_at(camera["eye"], camera["target"], camera["up"])).tolist())
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object

    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = float(spec["sun"]["irradiance"])  # W/m^2 on a surface facing it
    sun.angle = 0.0
    sun_object = bpy.data.objects.new("Sun", sun)
    # A sun shines along its local -z.
    sun_object.matrix_world = (-Vector(spec["sun"]["direction"])).to_track_quat("Z", "Y").to_matrix().to_4x4()
    scene.collection.objects.link(sun_object)

    world = bpy.data.worlds.new("World")
    if bpy.app.version < (5, 0, 0):  # Blender 5 always uses the node tree (use_nodes is deprecated)
        world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*[float(spec["world"])] * 3, 1.0)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world

    render, cycles = scene.render, scene.cycles
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y, render.resolution_percentage = camera["width"], camera["height"], 100
    render.film_transparent = False
    render.threads_mode, render.threads = "FIXED", 2
    cycles.device = "CPU"
    cycles.samples = int(spec["spp"])
    cycles.seed = int(spec["seed"])
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    bounces = int(spec["max_bounces"])
    cycles.max_bounces = bounces
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = bounces
    cycles.transparent_max_bounces = bounces
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = cycles.caustics_refractive = True
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    if hasattr(cycles, "light_sampling_threshold"):
        cycles.light_sampling_threshold = 0.0
    scene.cycles_curves.shape = "THICK"
    scene.view_settings.view_transform = "Standard"
    render.image_settings.file_format = "OPEN_EXR"
    render.image_settings.color_depth = "32"
    render.filepath = out_path
    bpy.ops.render.render(write_still=True)


main()
