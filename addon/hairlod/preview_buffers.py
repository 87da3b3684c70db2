"""Index buffers for drawing an LoD asset on the GPU (no bpy), over the vertex arrays
``LodAsset.preview_vertices`` makes (C++ lod/preview_vertices.h): camera-facing strips for thick hairs,
lines for strands, laid out as ``ViewSelection.indices`` expects (item-major, n_c control points per
item; two strip vertices per control point; strands in hierarchy order).

Drawing a selection without rebuilding index buffers: every level is cut once into blocks of whole
L0 clusters with static index buffers over all their segments (``cluster_blocks``,
``block_indices``); each vertex carries its L0 cluster and control point (``select_key``); per
frame the selection's level per cluster and segment goes to the GPU as a small texture
(``ViewSelection.frame_levels``), the shader drops the fragments of segments selected at another
level, and only blocks holding some segment selected at a level are drawn (``blocks_to_draw``).

Thick-hair vertices carry what the viewport shader needs to shade the aggregated BCSDF
(hair-lod-aggregated-bcsdf.txt Sec. 4): the centre, tangent, the major and minor semi-axis vectors
(the strip's width and the ray length through the ellipse come from them in the shader), and the
cluster's strand count n_total and density rho."""

import numpy as np

__all__ = ["cluster_items", "whole_chunks", "cluster_blocks", "block_indices", "blocks_to_draw"]


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


def blocks_to_draw(present, bounds):
    """bool per block of ``bounds`` (cluster_blocks): whether any of its clusters is ``present``
    (one level's column of ``ViewSelection.frame_levels``)."""
    present = np.asarray(present, dtype=bool)
    bounds = np.asarray(bounds, dtype=np.int64)
    if len(bounds) < 2:
        return np.zeros(0, bool)
    return np.logical_or.reduceat(present, bounds[:-1])
