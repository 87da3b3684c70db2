"""The LoD preview's hair drawn into colour and depth buffers of its own, with a projection whose
depth range holds only the hair (hairlod/depth_range.py says why), then composited into the viewport
with the viewport's own depth per pixel (shaders/hair_layer.frag.glsl)."""

from contextlib import contextmanager

import gpu
from gpu_extras.batch import batch_for_shader

from .shaders import glsl_source

_shader = None


def _composite_shader():
    global _shader
    if _shader is None:
        interface = gpu.types.GPUStageInterfaceInfo("hairlod_hair_layer_interface")
        interface.smooth('VEC2', "uv")
        info = gpu.types.GPUShaderCreateInfo()
        info.vertex_in(0, 'VEC2', "position")
        info.vertex_out(interface)
        info.sampler(0, 'FLOAT_2D', "hair_colour")
        info.push_constant('VEC4', "planes")
        info.push_constant('INT', "perspective")
        info.fragment_out(0, 'VEC4', "fragColor")
        info.vertex_source(glsl_source("hair_layer.vert.glsl"))
        info.fragment_source(glsl_source("hair_layer.frag.glsl"))
        _shader = gpu.shader.create_from_info(info)
    return _shader


class HairLayer:
    """A viewport's hair layer: rgb and the fitted window depth in alpha (RGBA32F), and a 32-bit depth
    buffer for the depth test, made again when the viewport's size changes."""

    def __init__(self):
        self.size = None
        self.colour = None
        self._depth = None
        self._framebuffer = None
        self._batch = None

    @contextmanager
    def drawing(self, size):
        """Binds the layer, cleared (no hair: depth 1), for drawing the hair with the fitted projection;
        restores the viewport's framebuffer and viewport rectangle after."""
        size = (max(1, int(size[0])), max(1, int(size[1])))
        if size != self.size:
            self.colour = gpu.types.GPUTexture(size, format='RGBA32F')
            self._depth = gpu.types.GPUTexture(size, format='DEPTH_COMPONENT32F')
            self._framebuffer = gpu.types.GPUFrameBuffer(color_slots=(self.colour,), depth_slot=self._depth)
            self.size = size
        viewport, blend = gpu.state.viewport_get(), gpu.state.blend_get()
        with self._framebuffer.bind():
            self._framebuffer.clear(color=(0.0, 0.0, 0.0, 1.0), depth=1.0)
            gpu.state.viewport_set(0, 0, *size)
            gpu.state.blend_set('NONE')  # alpha holds the depth
            yield
        gpu.state.blend_set(blend)
        gpu.state.viewport_set(*viewport)

    def composite(self, fitted):
        """Draws the layer into the bound (viewport) framebuffer: colour, and depth tested and written
        as the viewport's (fitted: depth_range.FittedDepth the layer was drawn with)."""
        shader = _composite_shader()
        if self._batch is None:
            self._batch = batch_for_shader(shader, 'TRIS', {"position": [(-1.0, -1.0), (3.0, -1.0), (-1.0, 3.0)]})
        shader.bind()
        shader.uniform_sampler("hair_colour", self.colour)
        shader.uniform_float("planes", tuple(float(v) for v in fitted.planes))
        shader.uniform_int("perspective", int(fitted.perspective))
        gpu.state.depth_test_set('LESS_EQUAL')
        gpu.state.depth_mask_set(True)
        self._batch.draw(shader)
        gpu.state.depth_mask_set(False)
        gpu.state.depth_test_set('NONE')
