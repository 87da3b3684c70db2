"""Vertex arrays for drawing an LoD asset on the GPU (no bpy): camera-facing strips for thick hairs,
lines for strands, laid out as ``ViewSelection.indices`` expects (item-major, n_c control points per
item; two strip vertices per control point; strands in hierarchy order).

Thick-hair vertices carry what the viewport shader needs to shade the aggregated BCSDF
(hair-lod-aggregated-bcsdf.txt Sec. 4): the centre, tangent, the major and minor semi-axis vectors
(the strip's width and the ray length through the ellipse come from them in the shader), and the
cluster's strand count n_total and density rho.
"""

import numpy as np

__all__ = ["strand_line_vertices", "thick_strip_vertices", "polyline_tangents"]


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
