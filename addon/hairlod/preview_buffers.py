"""Index buffers for drawing an LoD asset on the GPU (no bpy), over the vertex arrays
``LodAsset.preview_vertices`` makes (C++ lod/preview_vertices.h): camera-facing strips for thick hairs,
lines for strands, laid out as ``ViewSelection.indices`` expects (item-major, n_c control points per
item; two strip vertices per control point; strands in hierarchy order).

Drawing a selection without rebuilding index buffers: every level is cut once into blocks of whole
L0 clusters with static index buffers over all their segments (``cluster_blocks``,
``block_indices``); each vertex carries its L0 cluster and control point (``select_key``); per
frame the selection's level per cluster and segment goes to the GPU as a small texture
(``ViewSelection.frame_levels``), the shader drops the fragments of segments selected at another
level, and only blocks holding some segment selected at a level are drawn (``level_blocks``). A
sparse level is drawn from its selected segments alone: the strands' as an index list, a thick level's
fetched by the shader from textures (``hairlod.pulled_strips``).
Blocks whose every segment is at the level drawn (the same function's second flags) go through a shader
without that test: a fragment shader that may discard keeps the GPU from testing depth before
shading, and a near view's hidden strands were then all shaded.

Thick-hair vertices carry what the viewport shader needs to shade the aggregated BCSDF
(hair-lod-aggregated-bcsdf.txt Sec. 4): the centre, tangent, the major and minor semi-axis vectors
(the strip's width and the ray length through the ellipse come from them in the shader), and the
cluster's strand count n_total and density rho.

The strands' vertex LoD (hair-meshes-realtime.txt Sec. 3.6.2 halves a strand's vertices in power-of-2
steps): each block of the strand level also has index buffers that draw every strand through control
points 0, s, 2s, ... and its last (``STRAND_STRIDES``). Per frame each block takes the longest stride
whose chords stay within a tolerance in pixels of the control points they skip (``stride_deviation``
at the rest pose, ``view_block_strides``). The selection test is unchanged: a
fragment of chord (a, b) reads the level of segment floor(t), t running from a to b along it."""

import numpy as np

from . import _core

__all__ = ["BLOCK_SEGMENTS", "PREVIEW_VERTEX_TOLERANCE_PX", "cluster_items", "whole_chunks", "cluster_blocks", "block_indices", "level_blocks", "blocks_wasteful", "block_centres",
           "blocks_near_to_far", "STRAND_STRIDES",
           "strided_lines", "stride_deviation", "view_block_strides", "cluster_strides"]

# Segments per block of whole L0 clusters: a dense level draws its blocks that hold a selected
# segment, so blocks are small (one or two strand clusters, a few clusters of the finer thick
# levels). About 1100 blocks for 100k strands of 32 points; a frame draws only the flagged ones.
BLOCK_SEGMENTS = 1 << 12
# A thick level is drawn from its selected segments alone instead of its blocks when the blocks hold
# more than this many times its selected segments of segments selected at other levels
# (blocks_wasteful): a thick
# hair not selected is wider than the strands selected in its place, so those are many fragments shaded
# or tested and dropped. At a mid view of 100k strands the finer thick level's blocks held 7.5x what it
# selected, and drawing the thick levels took about 300 ms a redraw on llvmpipe against 30 ms from exact
# lists. A sparse thick level is drawn from its selected segments by the shader (pulled_strips): a
# change of them costs a texture of 8 bytes a segment, no index list.
THICK_WASTE_RATIO = 3.0
# Strides of the strand level's index buffers, finest first (1 draws every control point).
STRAND_STRIDES = (1, 2, 4, 8, 16)
# The viewport's default tolerance of the strands' vertex LoD, in pixels: half a pixel, the error the
# preview's lines (1 px, not anti-aliased) already have from snapping to pixel centres. Per block it is
# met by the worst strand of every cluster at the cluster's nearest depth, so most chords stay well
# within it. (The renderer's default, lod.DEFAULT_VERTEX_TOLERANCE_PX, is per strand and point.)
PREVIEW_VERTEX_TOLERANCE_PX = 0.5


def cluster_items(asset, level):
    """int64 [clusters + 1]: the items of L0 cluster c at ``level`` are [first[c], first[c + 1]) (thick
    hairs of a thick level; at the finest level, len(asset.levels), strands in hierarchy order)."""
    if level < len(asset.levels):
        return np.asarray(asset.levels[level].cluster_first, dtype=np.int64)
    # The strands of L0 hair h are positions [member_first[h], member_first[h + 1]) in hierarchy order.
    level0 = asset.levels[0]
    member_first = np.concatenate([[0], np.cumsum(level0.n_total, dtype=np.int64)])
    return member_first[np.asarray(level0.cluster_first, dtype=np.int64)]


def whole_chunks(offsets, limit):
    """Bounds [b_0 = 0, b_1, ..., C] of chunks of whole items (item i spans [offsets[i],
    offsets[i + 1])) of at most ``limit`` units each; a larger item is a chunk of its own, and
    empty items go with their neighbours."""
    offsets = np.asarray(offsets, dtype=np.int64)
    count = len(offsets) - 1
    bounds = [0]
    while bounds[-1] < count:
        first = bounds[-1]
        # The last item end within `limit` of the chunk's start; at least one item.
        end = int(np.searchsorted(offsets, offsets[first] + limit, side="right")) - 1
        bounds.append(min(max(end, first + 1), count))
    return bounds


def cluster_blocks(item_first, control_points, max_segments):
    """Cluster bounds [c_0 = 0, c_1, ..., C] of blocks of whole clusters holding at most
    ``max_segments`` segments each (whole_chunks over the clusters' segments)."""
    return whole_chunks(np.asarray(item_first, dtype=np.int64) * (control_points - 1), max_segments)


def block_indices(item_first, first_cluster, end_cluster, control_points, primitive):
    """uint32 element indices of every segment of the items of clusters [first_cluster, end_cluster),
    in the layout of ``ViewSelection.indices``: [S, 2] lines (k, k + 1) of control points, or [2 S, 3]
    strip triangles over vertices 2k .. 2k + 3."""
    item_first = np.asarray(item_first, dtype=np.int64)
    items = np.arange(item_first[first_cluster], item_first[end_cluster], dtype=np.int64)
    k = (items[:, None] * control_points + np.arange(control_points - 1)[None, :]).reshape(-1)
    if primitive == "lines":
        return np.ascontiguousarray(np.stack([k, k + 1], axis=1).astype(np.uint32))
    if primitive == "strips":
        v = 2 * k
        quads = np.stack([v, v + 1, v + 2, v + 1, v + 3, v + 2], axis=1)
        return np.ascontiguousarray(quads.reshape(-1, 3).astype(np.uint32))
    raise ValueError(f"primitive must be 'lines' or 'strips', got {primitive!r}")


def level_blocks(present, whole, level, bounds):
    """(to_draw, one_level), bool per block of ``bounds`` (cluster_blocks) of ``level``, from
    ``ViewSelection.frame_levels``' ``present`` and ``whole``: whether some visible cluster of the block
    has a segment at the level (the block is drawn), and whether every cluster of it is visible with
    all its segments at the level, so that its fragments need no test of the selection: the shader
    then has no discard, and the GPU may test depth before shading (C++ lod/view_selection.h)."""
    return _core.level_blocks(np.asarray(present, dtype=bool), np.asarray(whole, dtype=np.int8), int(level),
                              np.asarray(bounds, dtype=np.int64))


def blocks_wasteful(block_segments, to_draw, selected, ratio=None):
    """Whether the blocks flagged in ``to_draw`` (level_blocks), of ``block_segments`` segments each,
    hold more than ``ratio`` (default THICK_WASTE_RATIO) times the level's ``selected`` segments of
    segments selected elsewhere."""
    ratio = THICK_WASTE_RATIO if ratio is None else ratio
    drawn = int(np.asarray(block_segments, dtype=np.int64)[np.asarray(to_draw, dtype=bool)].sum())
    return drawn - int(selected) > ratio * int(selected)


def block_centres(cluster_bounds, bounds):
    """float64 [blocks, 3]: per block of ``bounds`` (cluster_blocks), the mean centre of its clusters'
    bounding spheres (``cluster_bounds`` [C, 4])."""
    bounds = np.asarray(bounds, dtype=np.int64)
    if len(bounds) < 2:
        return np.zeros((0, 3))
    sums = np.zeros((len(cluster_bounds) + 1, 3))
    np.cumsum(np.asarray(cluster_bounds, dtype=np.float64)[:, :3], axis=0, out=sums[1:])
    return (sums[bounds[1:]] - sums[bounds[:-1]]) / np.diff(bounds)[:, None]


def blocks_near_to_far(centres, model_view):
    """int64 [blocks]: blocks ordered nearest first by the view depth of their ``centres``
    (block_centres, object space) under the 4 x 4 ``model_view``: drawn in that order, the strands in
    front fill the depth buffer first and the GPU skips shading most of those behind (with the
    shader of level_blocks' one_level blocks)."""
    row = np.asarray(model_view, dtype=np.float64)[2]
    return np.argsort(-(np.asarray(centres) @ row[:3] + row[3]), kind="stable")  # the view looks down -z


def _stride_starts(control_points, stride):
    """First control points a = 0, stride, 2 stride, ... < n_c - 1 of the chords (a, min(a + stride, n_c - 1))."""
    return np.arange(0, control_points - 1, stride, dtype=np.int64)


def strided_lines(item_first, first_cluster, end_cluster, control_points, stride):
    """uint32 [S, 2] line element indices of the items of clusters [first_cluster, end_cluster) drawn
    at ``stride``: chords (a, min(a + stride, n_c - 1)) for a = 0, stride, ...; stride 1 gives
    block_indices(..., "lines")."""
    item_first = np.asarray(item_first, dtype=np.int64)
    items = np.arange(item_first[first_cluster], item_first[end_cluster], dtype=np.int64)
    starts = _stride_starts(control_points, stride)
    ends = np.minimum(starts + stride, control_points - 1)
    base = items[:, None] * control_points
    lines = np.stack([(base + starts[None, :]).reshape(-1), (base + ends[None, :]).reshape(-1)], axis=1)
    return np.ascontiguousarray(lines.astype(np.uint32))


def stride_deviation(points, control_points, item_first):
    """float32 [clusters, len(STRAND_STRIDES)]: per L0 cluster (items [item_first[c], item_first[c +
    1]), points [items n_c, 3]) and stride, the largest distance of a control point from the chord
    drawn in its place (C++ lod/vertex_lod.h; infinity where a point is not finite)."""
    return _core.stride_chord_deviation(np.ascontiguousarray(points, dtype=np.float32), int(control_points),
                                                 np.ascontiguousarray(item_first, dtype=np.int64), list(STRAND_STRIDES))


def view_block_strides(deviation, cluster_bounds, model_view, projection, viewport_size, tolerance_px, bounds):
    """int32 [blocks]: per block of ``bounds`` (cluster_blocks), the index into STRAND_STRIDES of the
    longest stride whose chords stay within ``tolerance_px`` pixels of the points they skip
    (``deviation``, stride_deviation) in every cluster of the block, a pixel the size of one at the
    nearest depth of the cluster's bounding sphere (``cluster_bounds`` [C, 4] at the pose drawn, object
    space, under the 4 x 4 ``model_view`` and ``projection`` of a viewport ``viewport_size`` (width,
    height) pixels); 0 (every point) where a sphere reaches the eye or ``tolerance_px`` is 0 (C++
    lod/vertex_lod.h)."""
    return _core.view_block_strides(np.ascontiguousarray(deviation, dtype=np.float32),
                                    np.ascontiguousarray(cluster_bounds, dtype=np.float32),
                                    np.ascontiguousarray(bounds, dtype=np.int64), np.asarray(model_view, np.float32),
                                    np.asarray(projection, np.float32), tuple(viewport_size), float(tolerance_px))


def cluster_strides(block_stride_index, bounds):
    """int32 [clusters]: the stride (a value of STRAND_STRIDES) each cluster is drawn at, its block's
    (what ViewSelection.strided_strand_lines and strided_strand_segments take)."""
    return np.repeat(np.asarray(STRAND_STRIDES, dtype=np.int32)[np.asarray(block_stride_index, dtype=np.int64)],
                     np.diff(np.asarray(bounds, dtype=np.int64)))
