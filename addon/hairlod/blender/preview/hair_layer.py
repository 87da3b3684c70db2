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

Each draw is one sample of the layer: lod_preview draws the first after a change at the pixels'
centres, and while the view is at rest, in the redraws Blender makes for its own anti-aliasing, more
samples moved by SAMPLE_OFFSETS within the pixel. accumulate() sums them (colour and depth where a
sample holds hair, and how many do), and the composite draws their mean, mixed with the viewport by
the share of samples that hold hair: a pixel shows the strands that cross it averaged over its area,
as a render's pixel does, where one sample shows the one strand nearest its centre.
"""

from contextlib import contextmanager

import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from .shaders import glsl_source

COLOUR_SLOT = 10     # sampler slot of the layer's colour in the strands' shading (which takes 0-9 for its own)
POSITIONS_SLOT = 11  # of the strands' positions


def _radical_inverse(index, base):
    """The index's digits in `base` mirrored about the point: the Halton sequence's coordinate."""
    value, scale = 0.0, 1.0 / base
    while index > 0:
        index, digit = divmod(index, base)
        value += digit * scale
        scale /= base
    return value


# The most samples a layer averages (Blender's largest viewport anti-aliasing, 32 samples).
MAX_SAMPLES = 32
# Where each sample of the layer looks within its pixel, in pixels from the centre, in [-0.5, 0.5):
# the first at the centre (the draw after a change, as a single sample was), the others the Halton
# (2, 3) points, any first k of which cover the pixel evenly.
SAMPLE_OFFSETS = tuple([(0.0, 0.0)] + [(_radical_inverse(i, 2) - 0.5, _radical_inverse(i, 3) - 0.5)
                                       for i in range(1, MAX_SAMPLES)])

# The strands' shading pass: one triangle over the layer at the far plane (window depth 1), which the
# depth test GREATER keeps only where hair was drawn.
_FAR_TRIANGLE_VERTEX = "void main() { gl_Position = vec4(position, 1.0, 1.0); }\n"

_shader = None
_accumulate_shader = None

# Adds one sample of the layer to the sums (drawn at the far plane, depth test GREATER: where it holds
# hair): its colour and 1 (a sample holding hair) into the first, its fitted window depth into the second.
_ACCUMULATE_FRAGMENT = """
void main()
{
  ivec2 texel = ivec2(gl_FragCoord.xy);
  fragColor = vec4(texelFetch(hair_colour, texel, 0).rgb, 1.0);
  depthSum = texelFetch(hair_depth, texel, 0).a;
}
"""


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
        info.push_constant('FLOAT', "samples")
        info.fragment_out(0, 'VEC4', "fragColor")
        info.vertex_source(glsl_source("hair_layer.vert.glsl"))
        info.fragment_source(glsl_source("hair_layer.frag.glsl"))
        _shader = gpu.shader.create_from_info(info)
    return _shader


def _accumulation_shader():
    global _accumulate_shader
    if _accumulate_shader is None:
        info = gpu.types.GPUShaderCreateInfo()
        info.vertex_in(0, 'VEC2', "position")
        info.sampler(0, 'FLOAT_2D', "hair_colour")
        info.sampler(1, 'FLOAT_2D', "hair_depth")
        info.fragment_out(0, 'VEC4', "fragColor")
        info.fragment_out(1, 'FLOAT', "depthSum")
        info.vertex_source(_FAR_TRIANGLE_VERTEX)
        info.fragment_source(_ACCUMULATE_FRAGMENT)
        _accumulate_shader = gpu.shader.create_from_info(info)
    return _accumulate_shader


class HairLayer:
    """A viewport's hair layer: rgb and the fitted window depth in alpha (RGBA32F); the strands'
    positions, w = 1 where a strand is the nearest hair (RGBA32F; fragment output 1 of every program
    drawing into the layer); the colour with those strands shaded (SRGB8_A8: display values, stored as
    the viewport's framebuffer stores them, so the composite writes the same 8-bit values; the depth
    stays in the first's alpha; RGBA16F changed dark pixels by up to 6/255); a 32-bit depth buffer
    for the depth test; and the samples' sums (RGBA32F: colour, samples holding hair; R32F: window
    depth): 60 bytes a pixel (55 MB at 1280 x 720). Made again when the viewport's size changes."""

    def __init__(self):
        self.size = None
        self.colour = None
        self.strand_positions = None
        self.shaded = None
        self._depth = None
        self._framebuffer = None
        self._shading_framebuffer = None
        self._result = None  # the sample just drawn: colour, or shaded once shade_strands ran
        self._batch = None
        self.summed = None   # the samples' colour (rgb) and how many hold hair (a), summed
        self.summed_depth = None
        self._accumulation_framebuffer = None
        self.samples = 0     # samples summed since the last first one

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
            self.summed = gpu.types.GPUTexture(size, format='RGBA32F')
            self.summed_depth = gpu.types.GPUTexture(size, format='R32F')
            self._accumulation_framebuffer = gpu.types.GPUFrameBuffer(color_slots=(self.summed, self.summed_depth),
                                                                      depth_slot=self._depth)
            self.samples = 0
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
        """One triangle over the whole layer (the vertex input `position` of every pass over it)."""
        if self._batch is None:
            self._batch = batch_for_shader(_composite_shader(), 'TRIS', {"position": [(-1.0, -1.0), (3.0, -1.0), (-1.0, 3.0)]})
        return self._batch

    def _over_hair(self, framebuffer, shader, blend_mode, bind):
        """Draws `shader` (bound, then bind(shader)) into `framebuffer` where the layer holds hair (the
        far-plane triangle, depth test GREATER against the layer's depth), blended by `blend_mode`;
        restores the viewport's rectangle and blend."""
        viewport, blend = gpu.state.viewport_get(), gpu.state.blend_get()
        with framebuffer.bind():
            gpu.state.viewport_set(0, 0, *self.size)
            gpu.state.blend_set(blend_mode)
            gpu.state.depth_test_set('GREATER')  # the triangle lies at depth 1: only where hair is
            gpu.state.depth_mask_set(False)
            shader.bind()
            bind(shader)
            self._triangle().draw(shader)
            gpu.state.depth_test_set('NONE')
        gpu.state.blend_set(blend)
        gpu.state.viewport_set(*viewport)

    def shade_strands(self, shader, bind):
        """Shades the strands left in the layer (after drawing()): `shader` (declare_strand_shading)
        after bind(shader), into the layer's shaded colour, which the composite then draws where the
        layer holds hair (the only pixels the pass writes: the rest is never read, and not cleared)."""
        def bind_layer(program):
            bind(program)
            program.uniform_sampler("hair_colour", self.colour)
            program.uniform_sampler("strand_positions", self.strand_positions)

        self._over_hair(self._shading_framebuffer, shader, 'NONE', bind_layer)
        self._result = self.shaded

    def accumulate(self, first):
        """Adds the sample just drawn (after drawing(), and shade_strands where shaded) to the sums;
        `first` starts them again from it (the first sample after a change)."""
        if first:
            self.summed.clear(format='FLOAT', value=(0.0, 0.0, 0.0, 0.0))
            self.summed_depth.clear(format='FLOAT', value=(0.0,))
            self.samples = 0

        def bind_sample(program):
            program.uniform_sampler("hair_colour", self._result)
            program.uniform_sampler("hair_depth", self.colour)

        # Blended one plus one: the sums.
        self._over_hair(self._accumulation_framebuffer, _accumulation_shader(), 'ADDITIVE_PREMULT', bind_sample)
        self.samples += 1

    def coverage(self):
        """The share of the samples that hold hair, per pixel: float32 [height, width], rows bottom-up
        (read back from the GPU: for benchmarks and tests)."""
        return self.pixels()[1]

    def pixels(self):
        """(the hair's colour per pixel, the mean over the samples holding hair: float32 [height, width, 3],
        0 where none does; the share of the samples that hold hair, float32 [height, width]), rows
        bottom-up: what the composite mixes with the viewport, before the framebuffer's 8-bit rounding
        (read back from the GPU: for benchmarks and tests)."""
        width, height = self.size
        summed = np.array(self.summed.read().to_list(), np.float32).reshape(height, width, 4)
        holding = summed[..., 3]
        colour = summed[..., :3] / np.maximum(holding, 1.0)[..., None]
        return colour, holding / float(max(self.samples, 1))

    def composite(self, fitted):
        """Draws the samples' mean into the bound (viewport) framebuffer: colour over the viewport's by
        the share of samples holding hair, depth tested and written as the viewport's (fitted:
        depth_range.FittedDepth the layer was drawn with)."""
        shader = _composite_shader()
        shader.bind()
        shader.uniform_sampler("hair_colour", self.summed)
        shader.uniform_sampler("hair_depth", self.summed_depth)
        shader.uniform_float("planes", tuple(float(v) for v in fitted.planes))
        shader.uniform_int("perspective", int(fitted.perspective))
        shader.uniform_float("samples", float(max(self.samples, 1)))
        blend = gpu.state.blend_get()
        gpu.state.blend_set('ALPHA')
        gpu.state.depth_test_set('LESS_EQUAL')
        gpu.state.depth_mask_set(True)
        self._triangle().draw(shader)
        gpu.state.depth_mask_set(False)
        gpu.state.depth_test_set('NONE')
        gpu.state.blend_set(blend)
