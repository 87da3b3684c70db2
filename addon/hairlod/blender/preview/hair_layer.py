"""The LoD preview's hair drawn into colour and depth buffers of its own, with a projection whose
depth range holds only the hair (hairlod/depth_range.py says why), then composited into the viewport
with the viewport's own depth per pixel (shaders/hair_layer.frag.glsl).

Strands are shaded in the layer, deferred: their pass leaves, where a strand is the nearest hair, its
unit tangent in the colour's rgb and its position in a second buffer (w = 1), and one pass over the
layer then shades each such pixel once (shade_strands; lod_preview builds its program, with the
shading's declarations). Drawn at the far plane with the depth test GREATER, that pass runs only
where the layer holds hair: the GPU tests depth before shading, and a software GPU would otherwise
run the shading for every pixel of the viewport. Shading every strand fragment as it was drawn
shaded a near view's pixels several times over (the depth test keeps only the nearest).
"""

from contextlib import contextmanager

import gpu
from gpu_extras.batch import batch_for_shader

from .shaders import glsl_source

COLOUR_SLOT = 10     # sampler slot of the layer's colour in the strands' shading (which takes 0-9 for its own)
POSITIONS_SLOT = 11  # of the strands' positions

# The strands' shading pass: one triangle over the layer at the far plane (window depth 1), which the
# depth test GREATER keeps only where hair was drawn.
_FAR_TRIANGLE_VERTEX = "void main() { gl_Position = vec4(position, 1.0, 1.0); }\n"

_shader = None


def declare_strand_shading(info):
    """Declares on a GPUShaderCreateInfo what the strands' shading pass has besides the shading: the
    far-plane triangle, the layer's colour and positions (hair_colour, strand_positions) and the one
    output. The caller adds the fragment source (shaders/strand_shading.frag.glsl and what it calls)."""
    info.vertex_in(0, 'VEC2', "position")
    info.sampler(COLOUR_SLOT, 'FLOAT_2D', "hair_colour")
    info.sampler(POSITIONS_SLOT, 'FLOAT_2D', "strand_positions")
    info.fragment_out(0, 'VEC4', "fragColor")
    info.vertex_source(_FAR_TRIANGLE_VERTEX)


def _composite_shader():
    global _shader
    if _shader is None:
        interface = gpu.types.GPUStageInterfaceInfo("hairlod_hair_layer_interface")
        interface.smooth('VEC2', "uv")
        info = gpu.types.GPUShaderCreateInfo()
        info.vertex_in(0, 'VEC2', "position")
        info.vertex_out(interface)
        info.sampler(0, 'FLOAT_2D', "hair_colour")
        info.sampler(1, 'FLOAT_2D', "hair_depth")
        info.push_constant('VEC4', "planes")
        info.push_constant('INT', "perspective")
        info.fragment_out(0, 'VEC4', "fragColor")
        info.vertex_source(glsl_source("hair_layer.vert.glsl"))
        info.fragment_source(glsl_source("hair_layer.frag.glsl"))
        _shader = gpu.shader.create_from_info(info)
    return _shader


class HairLayer:
    """A viewport's hair layer: rgb and the fitted window depth in alpha (RGBA32F); the strands'
    positions, w = 1 where a strand is the nearest hair (RGBA32F; fragment output 1 of every program
    drawing into the layer); the colour with those strands shaded (SRGB8_A8: display values, stored as
    the viewport's framebuffer stores them, so the composite writes the same 8-bit values; the depth
    stays in the first's alpha; RGBA16F changed dark pixels by up to 6/255); and a 32-bit depth buffer
    for the depth test: 40 bytes a pixel (37 MB at 1280 x 720, 20 before the strands were deferred).
    Made again when the viewport's size changes."""

    def __init__(self):
        self.size = None
        self.colour = None
        self.strand_positions = None
        self.shaded = None
        self._depth = None
        self._framebuffer = None
        self._shading_framebuffer = None
        self._result = None  # the texture the composite draws: colour, or shaded once shade_strands ran
        self._batch = None

    @contextmanager
    def drawing(self, size):
        """Binds the layer, cleared (no hair: depth 1), for drawing the hair with the fitted projection;
        restores the viewport's framebuffer and viewport rectangle after."""
        size = (max(1, int(size[0])), max(1, int(size[1])))
        if size != self.size:
            self.colour = gpu.types.GPUTexture(size, format='RGBA32F')
            self.strand_positions = gpu.types.GPUTexture(size, format='RGBA32F')
            self.shaded = gpu.types.GPUTexture(size, format='SRGB8_A8')
            self._depth = gpu.types.GPUTexture(size, format='DEPTH_COMPONENT32F')
            self._framebuffer = gpu.types.GPUFrameBuffer(color_slots=(self.colour, self.strand_positions),
                                                         depth_slot=self._depth)
            self._shading_framebuffer = gpu.types.GPUFrameBuffer(color_slots=(self.shaded,), depth_slot=self._depth)
            self.size = size
        viewport, blend = gpu.state.viewport_get(), gpu.state.blend_get()
        self._result = self.colour
        # Window depth 1: no hair. The positions need no clearing: the strands' pass reads them only
        # where hair was drawn, and every fragment drawn writes them (w = 0 but for a strand's).
        self.colour.clear(format='FLOAT', value=(0.0, 0.0, 0.0, 1.0))
        with self._framebuffer.bind():
            self._framebuffer.clear(depth=1.0)
            gpu.state.viewport_set(0, 0, *size)
            gpu.state.blend_set('NONE')  # alpha holds the depth
            yield
        gpu.state.blend_set(blend)
        gpu.state.viewport_set(*viewport)

    def _triangle(self):
        """One triangle over the whole layer (the vertex input `position` of both passes over it)."""
        if self._batch is None:
            self._batch = batch_for_shader(_composite_shader(), 'TRIS', {"position": [(-1.0, -1.0), (3.0, -1.0), (-1.0, 3.0)]})
        return self._batch

    def shade_strands(self, shader, bind):
        """Shades the strands left in the layer (after drawing()): `shader` (declare_strand_shading)
        after bind(shader), into the layer's shaded colour, which the composite then draws where the
        layer holds hair (the only pixels the pass writes: the rest is never read, and not cleared)."""
        viewport, blend = gpu.state.viewport_get(), gpu.state.blend_get()
        with self._shading_framebuffer.bind():
            gpu.state.viewport_set(0, 0, *self.size)
            gpu.state.blend_set('NONE')
            gpu.state.depth_test_set('GREATER')  # the triangle lies at depth 1: only where hair is
            gpu.state.depth_mask_set(False)
            shader.bind()
            bind(shader)
            shader.uniform_sampler("hair_colour", self.colour)
            shader.uniform_sampler("strand_positions", self.strand_positions)
            self._triangle().draw(shader)
            gpu.state.depth_test_set('NONE')
        gpu.state.blend_set(blend)
        gpu.state.viewport_set(*viewport)
        self._result = self.shaded

    def composite(self, fitted):
        """Draws the layer into the bound (viewport) framebuffer: colour, and depth tested and written
        as the viewport's (fitted: depth_range.FittedDepth the layer was drawn with)."""
        shader = _composite_shader()
        shader.bind()
        shader.uniform_sampler("hair_colour", self._result)
        shader.uniform_sampler("hair_depth", self.colour)
        shader.uniform_float("planes", tuple(float(v) for v in fitted.planes))
        shader.uniform_int("perspective", int(fitted.perspective))
        gpu.state.depth_test_set('LESS_EQUAL')
        gpu.state.depth_mask_set(True)
        self._triangle().draw(shader)
        gpu.state.depth_mask_set(False)
        gpu.state.depth_test_set('NONE')
