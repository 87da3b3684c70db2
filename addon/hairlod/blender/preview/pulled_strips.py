"""The GPU side of hairlod.pulled_strips: a sparse thick level drawn from its selected segments without
a per-frame index list (the layout and why are there; the shader is thick_hair.vert.glsl with
HAIRLOD_PULLED)."""

import gpu
import numpy as np

from ... import pulled_strips

POINTS_SLOT = 10    # sampler slot of a level's control points (the thick shader takes 0-9 for the rest)
SEGMENTS_SLOT = 11  # of the frame's selected segments


def declare(info):
    """Declares on a thick-hair GPUShaderCreateInfo what the pulled vertex shader reads (in place of the
    strip vertex attributes), and returns the defines its source needs."""
    info.vertex_in(0, 'INT', "slot_vertex")
    info.sampler(POINTS_SLOT, 'FLOAT_2D', "pulled_points")
    info.sampler(SEGMENTS_SLOT, 'FLOAT_2D', "pulled_segments")
    info.push_constant('INT', "pulled_count")
    return (f"#define HAIRLOD_PULLED\n#define POINT_TEXELS {pulled_strips.POINT_TEXELS}\n"
            f"#define POINT_ROW {pulled_strips.POINT_ROW}\n#define SEGMENT_ROW {pulled_strips.SEGMENT_ROW}\n")


def points_texture(arrays):
    """A thick level's control points (pulled_strips.point_texels of its strip vertex arrays) as an
    RGBA32F texture."""
    data = pulled_strips.point_texels(arrays)
    rows, width = data.shape[:2]
    data = data.ravel()
    return gpu.types.GPUTexture((width, rows), format='RGBA32F', data=gpu.types.Buffer('FLOAT', data.size, data))


class PulledDraw:
    """One frame's draw of a sparse thick level: its selected segments' texture and a slot batch that
    holds them."""

    def __init__(self, batch, points, segments, count):
        self.batch, self.points, self.segments, self.count = batch, points, segments, count

    def draw(self, program):
        """Draws with `program` (the pulled thick shader, bound, its other uniforms set)."""
        program.uniform_sampler("pulled_points", self.points)
        program.uniform_sampler("pulled_segments", self.segments)
        program.uniform_int("pulled_count", self.count)
        self.batch.draw(program)


class SlotBatches:
    """The static slot batches (pulled_strips.slot_elements), one per capacity, each made on first use
    and kept: the only index buffers a sparse thick level needs, whatever it selects."""

    def __init__(self):
        self._batches = {}
        self._texels = None  # the segment texels' memory, kept from frame to frame (segment_texels)

    def batch(self, segments):
        """The batch whose capacity (pulled_strips.slot_capacity) holds `segments` segments."""
        capacity = pulled_strips.slot_capacity(segments)
        if capacity not in self._batches:
            vertex_format = gpu.types.GPUVertFormat()
            vertex_format.attr_add(id="slot_vertex", comp_type='I32', len=1, fetch_mode='INT')
            vertices = gpu.types.GPUVertBuf(vertex_format, 4 * capacity)
            vertices.attr_fill("slot_vertex", np.arange(4 * capacity, dtype=np.int32))
            elements = gpu.types.GPUIndexBuf(type='TRIS', seq=pulled_strips.slot_elements(capacity))
            self._batches[capacity] = gpu.types.GPUBatch(type='TRIS', buf=vertices, elem=elements)
        return self._batches[capacity]

    def draw_of(self, starts, points):
        """The PulledDraw of the segments whose first control points are `starts`
        (ViewSelection.indices(level, "segments"), not empty) over a level's points texture."""
        if self._texels is None or len(self._texels) < pulled_strips.texel_rows(len(starts)) * pulled_strips.SEGMENT_ROW:
            # As many as the slot batch that draws them holds, so it grows as seldom as the batches.
            capacity = pulled_strips.slot_capacity(len(starts))
            self._texels = np.empty((pulled_strips.texel_rows(capacity) * pulled_strips.SEGMENT_ROW, 2), np.float32)
        data = pulled_strips.segment_texels(starts, out=self._texels)
        rows, width = data.shape[:2]
        data = data.ravel()
        segments = gpu.types.GPUTexture((width, rows), format='RG32F', data=gpu.types.Buffer('FLOAT', data.size, data))
        return PulledDraw(self.batch(len(starts)), points, segments, len(starts))
