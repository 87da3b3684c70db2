"""Thick-hair strips drawn without a per-frame index list (no bpy): the layout of the textures and
static buffers the viewport's "pulled" thick-hair shader reads (thick_hair.vert.glsl, HAIRLOD_PULLED).

A sparse thick level is drawn from its selected segments only. Blender 3.4's GPUBatch can neither
draw part of an index buffer nor update one, so that list was a new GPUIndexBuf every time the level's
selection moved: 6 indices a segment at 24-30 ns each inside the draw, 0.87 ms per frame on average
in the 100k-strand dolly (scripts/bench_lod_preview.py), half the selection + update. Here the
vertex shader fetches what it draws instead:

- the level's control points, once per asset, in a float texture (``point_texels``): 4 RGBA texels
  per point, POINT_ROW points per row, holding the strip vertex attributes of
  ``LodAsset.preview_vertices`` (position, tangent, major, minor, cluster, select_key);
- per frame, the selected segments' first points (``ViewSelection.indices(level, "segments")``) in a
  float texture (``segment_texels``), SEGMENT_ROW per row: 8 bytes a segment, a texture made in
  microseconds;
- a static batch of ``capacity`` slots (``slot_elements``): slot s is the quad of vertices 4s to 4s + 3
  (vertex 4s + 2c + side is control point c of the slot's segment, on side -1 or +1), whose vertex
  buffer holds each vertex's number. Slots past the frame's segment count collapse to a point outside
  the view. Capacities grow by sqrt(2) (``slot_capacity``), so at most 41 % of the slots drawn are
  empty, and each capacity's batch is made once.
"""

import bisect
import math
import sys

import numpy as np

__all__ = ["POINT_TEXELS", "POINT_ROW", "SEGMENT_ROW", "MIN_SLOTS", "point_texels", "segment_texels", "texel_rows",
           "slot_capacity", "slot_elements"]

POINT_TEXELS = 4       # RGBA texels per control point: 16 floats
POINT_ROW = 1024       # control points per row of the points texture (4096 texels, within every GPU's limit)
SEGMENT_ROW = 4096     # segments per row of the segments texture
MIN_SLOTS = 256        # the smallest capacity of a slot batch

# The strip vertex attributes in the order the texels hold them (3 + 3 + 3 + 3 + 2 + 2 = 16 floats).
# A uint32 viewed as two uint16 holds its low half first on a little-endian machine.
_LITTLE_ENDIAN = sys.byteorder == "little"

_ATTRIBUTES = (("position", 3), ("tangent", 3), ("major", 3), ("minor", 3), ("cluster", 2), ("select_key", 2))


def point_texels(arrays):
    """float32 [rows, POINT_ROW * POINT_TEXELS, 4]: the control points of one thick level from its strip
    vertex arrays (``preview_vertices()["levels"][level]``, two identical vertices per point), texels
    4i to 4i + 3 of row i // POINT_ROW holding point i's attributes in _ATTRIBUTES order; rows padded
    with zeros (at least one row)."""
    vertices = len(arrays["position"])
    if vertices % 2:
        raise ValueError(f"strip vertex arrays hold two vertices per control point, got {vertices} vertices")
    points = vertices // 2
    rows = max(1, -(-points // POINT_ROW))
    data = np.zeros((rows * POINT_ROW, POINT_TEXELS * 4), np.float32)
    column = 0
    for name, length in _ATTRIBUTES:
        values = np.asarray(arrays[name], dtype=np.float32)
        if values.shape != (vertices, length):
            raise ValueError(f"strip vertex array {name!r} has shape {values.shape}, expected ({vertices}, {length})")
        data[:points, column:column + length] = values[::2]
        column += length
    return data.reshape(rows, POINT_ROW * POINT_TEXELS, 4)


def segment_texels(starts, out=None):
    """float32 [rows, SEGMENT_ROW, 2]: the segments' first control points (uint32, from
    ``ViewSelection.indices(level, "segments")``) in rows of SEGMENT_ROW, each as its low and high 16
    bits, integers a float holds exactly (Blender 3.4 uploads float textures only); at least one row.
    Without `out` the last row is padded with zeros. With `out` (float32 [n, 2], C-contiguous, n at
    least rows x SEGMENT_ROW: see texel_rows) the texels are written into its first entries and a view
    of them returned; entries past the starts keep what they held (the shader reads none past the
    count). It runs in the draw, where every numpy call runs cold (tens of microseconds each) and a new
    array's pages fault in: one cast of the starts' halves into memory kept from frame to frame."""
    starts = np.asarray(starts)
    if starts.ndim != 1:
        raise ValueError(f"segment starts must be one-dimensional, got shape {starts.shape}")
    if starts.dtype != np.uint32:
        if starts.size and (int(starts.min()) < 0 or int(starts.max()) > np.iinfo(np.uint32).max):
            raise ValueError("segment starts must be unsigned 32-bit integers")
        starts = starts.astype(np.uint32)
    rows = texel_rows(len(starts))
    if out is None:
        data = np.zeros((rows * SEGMENT_ROW, 2), np.float32)
    else:
        if out.dtype != np.float32 or out.ndim != 2 or out.shape[1] != 2 or not out.flags.c_contiguous:
            raise ValueError(f"out must be a C-contiguous float32 array [n, 2], got {out.dtype} {out.shape}")
        if out.shape[0] < rows * SEGMENT_ROW:
            raise ValueError(f"out holds {out.shape[0]} texels, {len(starts)} segments need {rows * SEGMENT_ROW}")
        data = out[:rows * SEGMENT_ROW]
    halves = starts.view(np.uint16).reshape(-1, 2)
    data[:len(starts)] = halves if _LITTLE_ENDIAN else halves[:, ::-1]
    return data.reshape(rows, SEGMENT_ROW, 2)


def texel_rows(segments):
    """The rows of SEGMENT_ROW texels that ``segments`` segments take (at least one)."""
    return max(1, -(-segments // SEGMENT_ROW))


def _capacities():
    """MIN_SLOTS x sqrt(2)^j rounded up to an even number, ascending, up to the first past 2^32."""
    capacities, j = [], 0
    while not capacities or capacities[-1] <= 1 << 32:
        capacities.append(2 * -(-math.ceil(MIN_SLOTS * 2.0 ** (j / 2)) // 2))
        j += 1
    return tuple(capacities)


# Made once: the capacity is looked up on every change of a sparse level, inside the draw.
_CAPACITIES = _capacities()


def slot_capacity(segments):
    """The slots of the batch that draws ``segments`` (>= 0) segments: the smallest of MIN_SLOTS x
    sqrt(2)^j (rounded up to an even number) that holds them."""
    if not 0 <= segments <= _CAPACITIES[-1]:
        raise ValueError(f"segments must be >= 0 and at most {_CAPACITIES[-1]}, got {segments}")
    return _CAPACITIES[bisect.bisect_left(_CAPACITIES, segments)]


def slot_elements(capacity):
    """int32 [2 * capacity, 3]: the TRIS of ``capacity`` slots, slot s the quad (4s, 4s + 1, 4s + 2) and
    (4s + 1, 4s + 3, 4s + 2), the triangles ViewSelection's strips give a segment (side -1 on even
    vertices, control point 0 on the first two)."""
    first = 4 * np.arange(capacity, dtype=np.int32)[:, None]
    return (first + np.array([0, 1, 2, 1, 3, 2], np.int32)).reshape(-1, 3)
