"""A GPU batch of strand lines: positions, tangents and the position along the strand, with a
LINES index buffer, shaded by the Kajiya-Kay diffuse term with a root-to-tip colour ramp.

Buffers are filled from contiguous numpy arrays (no Python loop over strands or points). The
index buffer and the ramp parameter depend only on the curve offsets and are kept while those stay
the same, so regenerating strands of an unchanged topology uploads positions and tangents only.
"""

import os

import numpy as np

SHADER_FOLDER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shaders")

_shader = None


def line_indices(offsets):
    """[S, 2] int32 vertex pairs of the segments of the curves given by ``offsets`` (C + 1)."""
    offsets = np.asarray(offsets, dtype=np.int64)
    point_count = int(offsets[-1]) if len(offsets) else 0
    if point_count < 2:
        return np.empty((0, 2), np.int32)
    # Every point starts a segment except the last point of each curve.
    starts = np.ones(point_count - 1, bool)
    starts[offsets[1:-1] - 1] = False
    first = np.flatnonzero(starts).astype(np.int32)
    return np.stack([first, first + 1], axis=1)


def along_strand(offsets):
    """[N] float32: 0 at each curve's root, 1 at its tip, linear in the point index."""
    offsets = np.asarray(offsets, dtype=np.int64)
    counts = np.diff(offsets)
    index = np.arange(int(offsets[-1]) if len(offsets) else 0, dtype=np.int64) - np.repeat(offsets[:-1], counts)
    return (index / np.repeat(np.maximum(counts - 1, 1), counts)).astype(np.float32)


def _source(name):
    with open(os.path.join(SHADER_FOLDER, name), encoding="utf-8") as stream:
        return stream.read()


def strand_shader():
    """The strand shader (built once; needs a GPU context, so never in background mode)."""
    global _shader
    if _shader is None:
        import gpu

        info = gpu.types.GPUShaderCreateInfo()
        # 112 bytes of push constants: within the 128 that every backend guarantees.
        info.push_constant('MAT4', "model_view_projection")
        info.push_constant('VEC3', "light_direction")  # unit, object space, towards the light
        info.push_constant('VEC4', "root_colour")      # alpha: the ambient fraction of the shading
        info.push_constant('VEC4', "tip_colour")
        info.vertex_in(0, 'VEC3', "position")
        info.vertex_in(1, 'VEC3', "tangent")
        info.vertex_in(2, 'FLOAT', "along")
        interface = gpu.types.GPUStageInterfaceInfo("hairlod_strand_interface")
        interface.smooth('VEC3', "shade")
        info.vertex_out(interface)
        info.fragment_out(0, 'VEC4', "fragment_colour")
        info.vertex_source(_source("strands_vert.glsl"))
        info.fragment_source(_source("strands_frag.glsl"))
        _shader = gpu.shader.create_from_info(info)
    return _shader


class StrandBatch:
    """GPU buffers of one set of strands, rebuilt by ``update`` and drawn by ``draw``."""

    def __init__(self):
        self.batch = None
        self.strand_count = 0
        self.point_count = 0
        self._offsets = None
        self._indices = None
        self._along = None

    def update(self, points, tangents, offsets):
        """Replaces the strands: points and tangents [N, 3] (float32), offsets [C + 1]."""
        import gpu

        points = np.ascontiguousarray(points, dtype=np.float32).reshape(-1, 3)
        tangents = np.ascontiguousarray(tangents, dtype=np.float32).reshape(-1, 3)
        offsets = np.asarray(offsets, dtype=np.int64)
        if len(tangents) != len(points) or (len(offsets) and offsets[-1] != len(points)):
            raise ValueError(f"strand batch: {len(points)} points, {len(tangents)} tangents and offsets ending at "
                             f"{offsets[-1] if len(offsets) else None} do not match")
        if self._offsets is None or not np.array_equal(self._offsets, offsets):
            self._offsets = offsets.copy()
            self._indices = gpu.types.GPUIndexBuf(type='LINES', seq=line_indices(offsets))
            self._along = along_strand(offsets)
        self.strand_count, self.point_count = len(offsets) - 1, len(points)
        if len(points) < 2:
            self.batch = None
            return
        # A vertex buffer cannot be refilled once drawn: every update makes a new one.
        vertex_format = gpu.types.GPUVertFormat()
        vertex_format.attr_add(id="position", comp_type='F32', len=3, fetch_mode='FLOAT')
        vertex_format.attr_add(id="tangent", comp_type='F32', len=3, fetch_mode='FLOAT')
        vertex_format.attr_add(id="along", comp_type='F32', len=1, fetch_mode='FLOAT')
        vertices = gpu.types.GPUVertBuf(vertex_format, len(points))
        vertices.attr_fill("position", points)
        vertices.attr_fill("tangent", tangents)
        vertices.attr_fill("along", self._along)
        self.batch = gpu.types.GPUBatch(type='LINES', buf=vertices, elem=self._indices)

    def draw(self, model_view_projection, light_direction, root_colour, tip_colour):
        """Draws with depth test in the current framebuffer. ``light_direction`` is in the object
        space of the points; colours are RGBA with the ambient fraction in the root colour's alpha."""
        if self.batch is None:
            return
        import gpu

        shader = strand_shader()
        shader.bind()
        shader.uniform_float("model_view_projection", model_view_projection)
        shader.uniform_float("light_direction", light_direction)
        shader.uniform_float("root_colour", root_colour)
        shader.uniform_float("tip_colour", tip_colour)
        gpu.state.depth_test_set('LESS_EQUAL')
        gpu.state.depth_mask_set(True)
        self.batch.draw(shader)
        gpu.state.depth_test_set('NONE')
