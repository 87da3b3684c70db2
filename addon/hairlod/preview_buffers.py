"""Vertex arrays for drawing an LoD asset on the GPU (no bpy): camera-facing strips for thick hairs,
lines for strands, laid out as ``ViewSelection.indices`` expects (item-major, n_c control points per
item; two strip vertices per control point; strands in hierarchy order).

Drawing a selection without rebuilding index buffers: every level is cut once into blocks of whole
L0 clusters with static index buffers over all their segments (``cluster_blocks``,
``block_indices``); each vertex carries its L0 cluster and control point (``selection_keys``); per
frame the selection's level per cluster and segment goes to the GPU as a small texture
(``ViewSelection.frame_levels``), the shader drops the fragments of segments selected at another
level, and only blocks holding some segment selected at a level are drawn (``blocks_to_draw``).

Thick-hair vertices carry what the viewport shader needs to shade the aggregated BCSDF
(hair-lod-aggregated-bcsdf.txt Sec. 4): the centre, tangent, the major and minor semi-axis vectors
(the strip's width and the ray length through the ellipse come from them in the shader), and the
cluster's strand count n_total and density rho.
"""

import numpy as np

__all__ = ["strand_line_vertices", "thick_strip_vertices", "polyline_tangents", "cluster_items", "selection_keys",
           "whole_chunks", "cluster_blocks", "block_indices", "blocks_to_draw"]


def polyline_tangents(points):
    """Unit tangents [items, n, 3] of polylines [items, n, 3] (central differences, one-sided at the
    ends); a zero-length stretch gets the tangent (0, 0, 1) rather than NaN."""
    points = np.asarray(points, dtype=np.float32)
    if points.ndim != 3 or points.shape[1] < 2 or points.shape[2] != 3:
        raise ValueError(f"points must have shape [items, n >= 2, 3], got {list(points.shape)}")
    tangents = np.empty_like(points)
    tangents[:, 1:-1] = points[:, 2:] - points[:, :-2]
    tangents[:, 0] = points[:, 1] - points[:, 0]
    tangents[:, -1] = points[:, -1] - points[:, -2]
    length = np.linalg.norm(tangents, axis=2, keepdims=True)
    degenerate = length[..., 0] <= 1e-30
    tangents /= np.where(length > 1e-30, length, 1.0)
    tangents[degenerate] = (0.0, 0.0, 1.0)
    return tangents


def thick_strip_vertices(geometry_level, n_total, density):
    """Strip vertices of one thick level: ``geometry_level`` as ``LodAsset.skin`` returns a level
    (centres, tangents, major, minor [H, n_c, 3]), ``n_total`` [H] and ``density`` [H, n_c].
    Returns a dict of float32 arrays with 2 H n_c rows: position, tangent, major, minor (semi-axis
    vectors) and cluster (n_total, rho)."""
    centres = np.asarray(geometry_level["centres"], dtype=np.float32)
    hairs, control_points = centres.shape[:2]
    n_total = np.asarray(n_total, dtype=np.float32).reshape(hairs)
    density = np.asarray(density, dtype=np.float32).reshape(hairs, control_points)

    def twice(array, components):
        return np.ascontiguousarray(np.repeat(np.asarray(array, dtype=np.float32).reshape(-1, components), 2, axis=0))

    cluster = np.stack([np.repeat(n_total, control_points), density.reshape(-1)], axis=1)
    return {"position": twice(centres, 3), "tangent": twice(geometry_level["tangents"], 3),
            "major": twice(geometry_level["major"], 3), "minor": twice(geometry_level["minor"], 3),
            "cluster": twice(cluster, 2)}


def strand_line_vertices(strands, strand_order, control_points):
    """Line vertices of the strands (each with ``control_points`` points, in input order) reordered
    into hierarchy order ``strand_order``. Returns position and tangent, float32 [C n_c, 3]."""
    points = np.asarray(strands.points, dtype=np.float32)
    order = np.asarray(strand_order, dtype=np.int64)
    if points.shape[0] != order.size * control_points:
        raise ValueError(f"expected {order.size} strands of {control_points} points, got {points.shape[0]} points")
    ordered = points.reshape(-1, control_points, 3)[order]
    return {"position": np.ascontiguousarray(ordered.reshape(-1, 3)),
            "tangent": np.ascontiguousarray(polyline_tangents(ordered).reshape(-1, 3))}


def cluster_items(asset, level):
    """int64 [clusters + 1]: the items of L0 cluster c at ``level`` are [first[c], first[c + 1]) (thick
    hairs of a thick level; at the finest level, len(asset.levels), strands in hierarchy order)."""
    if level < len(asset.levels):
        return np.asarray(asset.levels[level].cluster_first, dtype=np.int64)
    level0 = asset.arrays()["levels"][0]
    return np.asarray(level0["member_first"], dtype=np.int64)[np.asarray(level0["cluster_first"], dtype=np.int64)]


def selection_keys(item_first, control_points, vertices_per_point):
    """float32 [items n_c vertices_per_point, 2]: each vertex's L0 cluster and control point index
    (item-major; 2 vertices per point for strips, 1 for lines)."""
    item_first = np.asarray(item_first, dtype=np.int64)
    clusters = np.repeat(np.arange(len(item_first) - 1), np.diff(item_first))
    per_point = np.stack([np.repeat(clusters, control_points),
                          np.tile(np.arange(control_points), len(clusters))], axis=1).astype(np.float32)
    return np.ascontiguousarray(np.repeat(per_point, vertices_per_point, axis=0))


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
