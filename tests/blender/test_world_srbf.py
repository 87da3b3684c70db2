"""The world as SRBF lights reads an Environment Texture in the directions Cycles shows it: the image
is rendered as the background by Cycles through a narrow camera looking along a few directions, and
the colour seen must be the image's at the pixel hairlod.world_lighting maps that direction to."""

import math

import bpy
import numpy as np
import pytest
from mathutils import Euler, Vector

from hairlod.blender.versions import enable_nodes
from hairlod.world_lighting import blender_equirectangular_directions

WIDTH, HEIGHT = 64, 32


@pytest.fixture
def environment_scene(tmp_path):
    # Quadrants of distinct colours: red / blue halves in u, green added in the top rows.
    pixels = np.zeros((HEIGHT, WIDTH, 4), np.float32)
    pixels[..., 3] = 1.0
    pixels[:, :WIDTH // 2, 0] = 1.0
    pixels[:, WIDTH // 2:, 2] = 1.0
    pixels[3 * HEIGHT // 4:, :, 1] = 1.0
    image = bpy.data.images.new("hairlod_env_test", WIDTH, HEIGHT, float_buffer=True)
    image.pixels.foreach_set(pixels.ravel())
    scene = bpy.data.scenes.new("hairlod_env_test")
    world = bpy.data.worlds.new("hairlod_env_test")
    enable_nodes(world)
    environment = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    environment.image = image
    environment.interpolation = 'Closest'
    world.node_tree.links.new(environment.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    scene.world = world
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 4
    scene.render.image_settings.file_format = 'OPEN_EXR'
    camera = bpy.data.objects.new("hairlod_env_test", bpy.data.cameras.new("hairlod_env_test"))
    camera.data.angle = 0.05
    scene.collection.objects.link(camera)
    scene.camera = camera
    yield scene, camera, pixels, tmp_path
    bpy.data.scenes.remove(scene)
    bpy.data.worlds.remove(world)
    bpy.data.images.remove(image)


def test_environment_directions_match_cycles(environment_scene):
    scene, camera, pixels, folder = environment_scene
    directions, _ = blender_equirectangular_directions(HEIGHT, WIDTH)
    # Away from the poles and from the colour edges, so one pixel's colour is seen.
    for index, (pitch, yaw) in enumerate(((90, 45), (90, 135), (90, 225), (90, 315), (150, 60), (30, 200))):
        rotation = Euler((math.radians(pitch), 0.0, math.radians(yaw)))
        camera.rotation_euler = rotation
        forward = np.array(rotation.to_matrix() @ Vector((0.0, 0.0, -1.0)))  # a camera looks along -z
        path = str(folder / f"env_{index}.exr")
        scene.render.filepath = path
        with bpy.context.temp_override(scene=scene):
            bpy.ops.render.render(write_still=True, scene=scene.name)
        rendered = bpy.data.images.load(path)
        seen = np.array(rendered.pixels[:], np.float32).reshape(4, 4, 4)[1:3, 1:3, :3].mean(axis=(0, 1))
        bpy.data.images.remove(rendered)
        row, column = np.unravel_index(np.argmax(directions.reshape(-1, 3) @ forward), (HEIGHT, WIDTH))
        np.testing.assert_allclose(seen, pixels[row, column, :3], atol=0.05,
                                   err_msg=f"looking along {forward.round(2)}: mapped to row {row}, column {column}")


def test_world_block_holds_only_the_lobes_that_carry_light():
    """The shader loops over every lobe the block gives it: a uniform world (the default world) gives
    none, and lobes of coefficient 0 are left out of any fit, the others kept in order."""
    from hairlod.blender.preview import world_srbf
    from hairlod.world_lighting import WorldLights, srbf_mean, uniform_world

    uniform = uniform_world((0.2, 0.3, 0.4), world_srbf.MAX_LOBES)
    data = world_srbf.world_block_data(uniform)
    assert data[4] == 0.0
    np.testing.assert_allclose(data[0:4], (0.2, 0.3, 0.4, 1.0), rtol=1e-6)

    directions = np.eye(3)[[0, 1, 2, 0]] * np.array([[1.0], [1.0], [1.0], [-1.0]])
    coefficients = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 2.0]])
    lights = WorldLights(constant=np.array([0.1, 0.1, 0.1]), directions=directions, lam=4.0,
                         coefficients=coefficients, relative_error=0.0)
    data = world_srbf.world_block_data(lights)
    assert data[4] == 2.0
    block_directions = data[8:8 + 4 * world_srbf.MAX_LOBES].reshape(-1, 4)
    block_colours = data[8 + 4 * world_srbf.MAX_LOBES:].reshape(-1, 4)
    np.testing.assert_array_equal(block_directions[:2, :3], directions[[1, 3]])
    np.testing.assert_array_equal(block_colours[:2, :3], coefficients[[1, 3]])
    # Each lobe's mean over the sphere, the light the hair around a point scatters on (hair_shading.glsl).
    np.testing.assert_allclose(block_colours[:2, 3], srbf_mean(4.0), rtol=1e-6)
    assert not block_colours[2:].any()
    assert world_srbf.world_block_data(None)[3] == 0.0  # the ambient path


def studio_world(name):
    """A world lit by one of Blender's own studio-light HDRIs. Every Blender release ships them in
    datafiles/studiolights/world (the Look Dev worlds), as Blender 3.4 and 4.3 here do, and the preview
    benchmark's --hdri and the UI test read them too: one missing is a broken install, not a case to skip."""
    import os

    folder = bpy.utils.system_resource('DATAFILES', path=os.path.join("studiolights", "world"))
    path = os.path.join(folder or "", name)
    assert os.path.isfile(path), f"Blender's studio-light world {name} is missing from {folder!r}"
    world = bpy.data.worlds.new(f"hairlod_{name}")
    enable_nodes(world)
    environment = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    environment.image = bpy.data.images.load(path, check_existing=True)
    world.node_tree.links.new(environment.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    return world, environment.image


def test_the_sun_of_an_hdri_becomes_a_light_and_a_sky_without_one_gives_none():
    """Blender's sunrise.exr holds 59 % of its light in 4e-4 sr: world_lights takes it out as a sun
    towards its brightest texels with most of the world's light; courtyard.exr (no texel over 69x its
    mean) keeps all of it in the fit."""
    from hairlod.blender.preview import world_srbf

    world, image = studio_world("sunrise.exr")
    lights, reason = world_srbf.world_lights(world)
    assert reason is None and lights.sun_direction is not None
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    rgb = np.maximum(pixels.reshape(height, width, 4)[..., :3], 0.0).astype(np.float64)
    directions, solid_angles = blender_equirectangular_directions(height, width)
    luminance = rgb @ np.array([0.2126, 0.7152, 0.0722])
    brightest = directions[np.unravel_index(np.argmax(luminance), luminance.shape)]
    assert math.degrees(math.acos(min(1.0, float(lights.sun_direction @ brightest)))) < 3.0
    sun_light = float(lights.sun_irradiance @ np.array([0.2126, 0.7152, 0.0722]))
    assert sun_light > 0.5 * float(np.sum(luminance * solid_angles))
    courtyard, _ = studio_world("courtyard.exr")
    lights, reason = world_srbf.world_lights(courtyard)
    assert reason is None and lights.sun_direction is None
