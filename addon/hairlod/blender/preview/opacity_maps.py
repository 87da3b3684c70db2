"""The GPU side of the preview's deep opacity maps (hairlod/opacity_map.py has the geometry and the
formulas; shaders/opacity_map.glsl reads the maps, shaders/opacity_pass.frag.glsl draws them).

An atlas holds one tile per mapped light: a depth texture (R32F, the depth of the first hair from the
light, kept by a depth test) and an opacity texture (RGBA32F, the optical depth of the hair above each
of the four layers, added up by additive blending). Both passes draw the hair as the light sees it,
from one level, with the preview's own vertex shaders (lod_preview passes the programs and the
geometry). The maps are drawn again only when the lights, the object's matrix or the hair's pose
change: orbiting the view costs nothing.
"""

import gpu
import numpy as np

from ... import opacity_map

DEPTH_SLOT = 4    # sampler slot of "depth_map" (the BCSDF tables take 0-2, the world's 3, the selection 6)
OPACITY_SLOT = 5  # of "opacity_map"
NO_HAIR_DEPTH = 1e30  # the depth map where the light meets no hair (opacity_map.glsl tests < 1e29)


def glsl_constants(opacity_pass=None):
    """#defines of opacity_map.glsl and, for a light pass, which one (0: depth, 1: opacity)."""
    text = (f"#define OPACITY_TILE {opacity_map.TILE}\n#define OPACITY_MAX_PIXEL_DEPTH {opacity_map.MAX_PIXEL_DEPTH!r}\n"
            f"#define OPACITY_MAX_LIGHTS {opacity_map.MAX_SHADOWED_LIGHTS}\n"
            f"#define OPACITY_LAYER_STEPS vec4{tuple(float(step) for step in opacity_map.LAYER_STEPS)}\n")
    if opacity_pass is not None:
        text += f"#define HAIRLOD_PI 3.14159265358979\n#define OPACITY_PASS {int(opacity_pass)}\n"
    return text


def declare(info, depth=True, opacity=True):
    """Declares the maps' samplers on a GPUShaderCreateInfo."""
    if depth:
        info.sampler(DEPTH_SLOT, 'FLOAT_2D', "depth_map")
    if opacity:
        info.sampler(OPACITY_SLOT, 'FLOAT_2D', "opacity_map")


class LightShadows:
    """What the shading pass reads of the maps, per light k < MAX_SHADOWED_LIGHTS: its view
    (view_projection [k]) and (pixel size, perspective, layer spacing, 1 when mapped) in
    `light_shadow` [k]."""

    def __init__(self):
        count = opacity_map.MAX_SHADOWED_LIGHTS
        self.view_projection = np.tile(np.eye(4, dtype=np.float32), (count, 1, 1))
        self.light_shadow = np.zeros((count, 4), np.float32)

    @property
    def mapped(self):
        return np.flatnonzero(self.light_shadow[:, 3] > 0.5)


def light_shadows(light_count, light_vectors, centre, radius):
    """LightShadows of the scene's first lights (light_vectors as lod_preview.scene_lights gives them)
    around the hair's bounding sphere (world space); a point light inside the sphere is not mapped."""
    shadows = LightShadows()
    spacing = opacity_map.layer_spacing(radius)
    for k in range(min(int(light_count), opacity_map.MAX_SHADOWED_LIGHTS)):
        projection = opacity_map.light_projection(light_vectors[k], centre, radius)
        if projection is None:
            continue
        shadows.view_projection[k] = projection.view_projection
        shadows.light_shadow[k] = (projection.pixel_size, float(projection.perspective), spacing, 1.0)
    return shadows


class OpacityMaps:
    """The atlas textures and their framebuffers, drawn again when `key` changes."""

    def __init__(self):
        size = (opacity_map.TILE * opacity_map.MAX_SHADOWED_LIGHTS, opacity_map.TILE)
        self.depth = gpu.types.GPUTexture(size, format='R32F')
        self.opacity = gpu.types.GPUTexture(size, format='RGBA32F')
        self._depth_buffer = gpu.types.GPUTexture(size, format='DEPTH_COMPONENT32F')
        self._depth_pass = gpu.types.GPUFrameBuffer(color_slots=(self.depth,), depth_slot=self._depth_buffer)
        self._opacity_pass = gpu.types.GPUFrameBuffer(color_slots=(self.opacity,))
        self.key = None

    def bind(self, program):
        program.uniform_sampler("depth_map", self.depth)
        program.uniform_sampler("opacity_map", self.opacity)

    def render(self, key, tiles, programs, draw):
        """Draws the maps unless they were drawn for `key`. `tiles`: (tile index, frame uniform block)
        per mapped light; `programs`: per pass (depth, opacity) a function binding that pass's program for
        a tile and returning it; `draw(program)` draws the hair's geometry."""
        if key == self.key:
            return False
        viewport, blend = gpu.state.viewport_get(), gpu.state.blend_get()
        tile = opacity_map.TILE
        with self._depth_pass.bind():
            self._depth_pass.clear(color=(NO_HAIR_DEPTH, 0.0, 0.0, 0.0), depth=1.0)
            gpu.state.blend_set('NONE')
            gpu.state.depth_test_set('LESS')
            gpu.state.depth_mask_set(True)
            for index, frame in tiles:
                gpu.state.viewport_set(index * tile, 0, tile, tile)
                draw(programs[0](index, frame))
        gpu.state.depth_mask_set(False)
        gpu.state.depth_test_set('NONE')
        with self._opacity_pass.bind():
            self._opacity_pass.clear(color=(0.0, 0.0, 0.0, 0.0))
            gpu.state.blend_set('ADDITIVE_PREMULT')  # dst + src in every channel
            for index, frame in tiles:
                gpu.state.viewport_set(index * tile, 0, tile, tile)
                program = programs[1](index, frame)
                program.uniform_sampler("depth_map", self.depth)
                draw(program)
        gpu.state.blend_set(blend)
        gpu.state.viewport_set(*viewport)
        self.key = key
        return True

    def read(self):
        """(depth [H, W], opacity [H, W, 4]) of the atlas, float32 (for tests)."""
        width, height = opacity_map.TILE * opacity_map.MAX_SHADOWED_LIGHTS, opacity_map.TILE
        depth = np.array(self.depth.read().to_list(), np.float32).reshape(height, width, -1)[..., 0]
        opacity = np.array(self.opacity.read().to_list(), np.float32).reshape(height, width, 4)
        return depth, opacity
