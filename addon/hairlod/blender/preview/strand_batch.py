"""GPU batches of strand lines: positions, tangents and the position along the strand, with LINES
index buffers, shaded by the Kajiya-Kay diffuse term with a root-to-tip colour ramp.

Buffers are filled from contiguous numpy arrays (no Python loop over strands or points). Each
attribute has a vertex buffer of its own: Blender fills a one-attribute buffer with one memcpy but
an interleaved one vertex by vertex (1.7M points: 4 ms against 110 ms). The strands are split
into chunks of whole curves of at most CHUNK_POINTS points: a vertex buffer cannot be refilled
once drawn, so every update allocates new ones, and allocations under malloc's largest mmap
threshold (32 MiB) reuse the memory the previous update freed instead of page-faulting fresh
pages. Index buffers and the ramp's vertex buffers depend only on a chunk's curve sizes: chunks of
equal sizes share them, and they are kept while the topology stays the same, so a regeneration of
unchanged topology uploads positions and tangents only.
"""

import numpy as np

from .shaders import glsl_source


_shader = None


# Points per chunk: 12 bytes each per position or tangent buffer, 0.75 MiB per chunk. Measured for
# 1.7M points (one buffer per attribute): 4.4 ms to fill in chunks of 2^16, 10 ms unsplit.
CHUNK_POINTS = 1 << 16


def _single_format(name, length):
    import gpu

    vertex_format = gpu.types.GPUVertFormat()
    vertex_format.attr_add(id=name, comp_type='F32', len=length, fetch_mode='FLOAT')
    return vertex_format


def attribute_buffer(name, values):
    """A vertex buffer of one attribute, filled with one copy of the contiguous ``values``: Blender
    fills a one-attribute buffer with a single memcpy, an interleaved one vertex by vertex."""
    import gpu

    values = np.ascontiguousarray(values, dtype=np.float32)
    length = 1 if values.ndim == 1 else values.shape[1]
    buffer = gpu.types.GPUVertBuf(_single_format(name, length), len(values))
    buffer.attr_fill(name, values)
    return buffer


def chunk_curves(offsets, chunk_points=CHUNK_POINTS):
    """Curve index bounds [c_0 = 0, c_1, ..., C] of chunks of whole curves with at most
    ``chunk_points`` points each (a longer curve is a chunk of its own)."""
    from ...preview_buffers import whole_chunks

    return whole_chunks(offsets, chunk_points)


def line_indices(offsets):
    """[S, 2] int32 vertex pairs of the segments of the curves given by ``offsets`` (C + 1)."""
    offsets = np.asarray(offsets, dtype=np.int64)
    point_count = int(offsets[-1]) if len(offsets) else 0
    if point_count < 2:
        return np.empty((0, 2), np.int32)
    counts = np.diff(offsets)
    if (counts == counts[0]).all():
        # Curves of one size (what the generator makes): one pattern shifted per curve.
        first = (offsets[:-1, None] + np.arange(counts[0] - 1)[None, :]).astype(np.int32).reshape(-1)
        return np.stack([first, first + 1], axis=1)
    # Every point starts a segment except the last point of each curve.
    starts = np.ones(point_count - 1, bool)
    starts[offsets[1:-1] - 1] = False
    first = np.flatnonzero(starts).astype(np.int32)
    return np.stack([first, first + 1], axis=1)


def along_strand(offsets):
    """[N] float32: 0 at each curve's root, 1 at its tip, linear in the point index."""
    offsets = np.asarray(offsets, dtype=np.int64)
    counts = np.diff(offsets)
    if len(counts) and (counts == counts[0]).all():
        ramp = np.linspace(0.0, 1.0, int(counts[0])) if counts[0] > 1 else np.zeros(1)
        return np.tile(ramp.astype(np.float32), len(counts))
    index = np.arange(int(offsets[-1]) if len(offsets) else 0, dtype=np.int64) - np.repeat(offsets[:-1], counts)
    return (index / np.repeat(np.maximum(counts - 1, 1), counts)).astype(np.float32)


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
        info.vertex_source(glsl_source("strands_vert.glsl"))
        info.fragment_source(glsl_source("strands_frag.glsl"))
        _shader = gpu.shader.create_from_info(info)
    return _shader


class StrandBatch:
    """GPU buffers of one set of strands, rebuilt by ``update`` and drawn by ``draw``."""

    def __init__(self):
        self.batches = []
        self.strand_count = 0
        self.point_count = 0
        self._offsets = None
        self._chunks = []  # (first point, last point, index buffer, ramp vertex buffer) per chunk

    def _chunk_topology(self, offsets):
        import gpu

        shared = {}
        self._chunks = []
        bounds = chunk_curves(offsets)
        for first, last in zip(bounds[:-1], bounds[1:]):
            local = offsets[first:last + 1] - offsets[first]
            key = local.tobytes()
            if key not in shared:
                shared[key] = (gpu.types.GPUIndexBuf(type='LINES', seq=line_indices(local)),
                               attribute_buffer("along", along_strand(local)))
            self._chunks.append((int(offsets[first]), int(offsets[last])) + shared[key])

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
            self._chunk_topology(offsets)
        self.strand_count, self.point_count = max(len(offsets) - 1, 0), len(points)
        self.batches = []
        for first, last, indices, along in self._chunks:
            if last - first < 2:
                continue
            # A vertex buffer cannot be refilled once drawn: every update makes new ones.
            batch = gpu.types.GPUBatch(type='LINES', buf=attribute_buffer("position", points[first:last]), elem=indices)
            batch.vertbuf_add(attribute_buffer("tangent", tangents[first:last]))
            batch.vertbuf_add(along)
            self.batches.append(batch)

    def draw(self, model_view_projection, light_direction, root_colour, tip_colour):
        """Draws with depth test in the current framebuffer. ``light_direction`` is in the object
        space of the points; colours are RGBA with the ambient fraction in the root colour's alpha."""
        if not self.batches:
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
        for batch in self.batches:
            batch.draw(shader)
        gpu.state.depth_test_set('NONE')
