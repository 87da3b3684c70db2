"""The viewport preview's vertex LoD of the strands (preview_buffers, no bpy): static index buffers per
power-of-2 stride, chosen per block from the chords' deviation at the clusters' distance."""

import numpy as np
import pytest

from hairlod import lod, preview_buffers
from hairlod.camera import look_at, perspective

STRIDES = preview_buffers.STRAND_STRIDES


@pytest.fixture(scope="module")
def real_asset(real_hair):
    asset = lod.build_lod(real_hair)
    vertices = asset.preview_vertices()
    first = preview_buffers.cluster_items(asset, len(asset.levels))
    return asset, vertices["strands"]["position"], first


def _chord_spans(lines, control_points):
    """Per line (v0, v1): item and the segments [k0, k1) it spans."""
    lines = np.asarray(lines, np.int64)
    items, k0 = np.divmod(lines[:, 0], control_points)
    items1, k1 = np.divmod(lines[:, 1], control_points)
    assert np.array_equal(items, items1), "a chord joins two items"
    return items, k0, k1


@pytest.mark.parametrize("control_points", [2, 5, 16, 17])
def test_each_stride_draws_every_items_segments_once(control_points):
    item_first = np.array([0, 3, 3, 7])
    for stride in STRIDES:
        lines = preview_buffers.strided_lines(item_first, 0, 3, control_points, stride)
        items, k0, k1 = _chord_spans(lines, control_points)
        covered = np.zeros((7, control_points - 1), np.int64)
        for item, a, b in zip(items, k0, k1):
            assert 0 < b - a <= stride and a % stride == 0
            covered[item, a:b] += 1
        np.testing.assert_array_equal(covered, 1)
    np.testing.assert_array_equal(preview_buffers.strided_lines(item_first, 1, 3, control_points, 1),
                                  preview_buffers.block_indices(item_first, 1, 3, control_points, "lines"))


def test_stride_deviation_is_each_points_distance_from_its_chord(real_asset):
    asset, points, first = real_asset
    n_c = asset.control_points
    deviation = preview_buffers.stride_deviation(points, n_c, first)
    assert deviation.shape == (asset.cluster_count, len(STRIDES)) and deviation.dtype == np.float32
    np.testing.assert_array_equal(deviation[:, 0], 0.0)
    # Brute force in float64 over every strand of every cluster.
    curves = np.asarray(points, np.float64).reshape(-1, n_c, 3)
    for j, stride in enumerate(STRIDES[1:], start=1):
        k = np.arange(n_c)
        a = k // stride * stride
        b = np.minimum(a + stride, n_c - 1)
        pa, pb, p = curves[:, a], curves[:, b], curves
        chord = pb - pa
        t = np.clip(np.sum((p - pa) * chord, axis=2) / np.maximum(np.sum(chord * chord, axis=2), 1e-300), 0.0, 1.0)
        distance = np.linalg.norm(p - pa - t[..., None] * chord, axis=2).max(axis=1)
        expected = np.maximum.reduceat(distance, first[:-1])
        np.testing.assert_allclose(deviation[:, j], expected, rtol=1e-4, atol=1e-7)


def _pixel(depth, fov_y=np.radians(40), height=500):
    """World length of a pixel at `depth` for a perspective camera of `fov_y` on `height` pixels."""
    return 2.0 * depth * np.tan(fov_y / 2.0) / height


def test_each_block_takes_the_longest_stride_its_clusters_allow_at_their_nearest_depth():
    projection = perspective(np.radians(40), 1.0, 0.1, 100.0)
    # Three clusters on the view axis (the camera at the origin looking down -z), nearest depths 9, 9, 4.
    bounds = np.array([[0, 0, -10, 1], [0, 0, -10, 1], [0, 0, -5, 1]], np.float32)
    deviation = np.array([[0, 1, 2, 4, 8], [0, 1, 3, 9, 9], [0, 0.5, 0.5, 0.5, 5]], np.float32) * _pixel(9.0)

    def strides(tolerance, blocks, cluster_bounds=bounds, model_view=np.eye(4), projection=projection):
        return preview_buffers.view_block_strides(deviation, cluster_bounds, model_view, projection, (500, 500),
                                                  tolerance, blocks).tolist()

    # 2.5 px at depth 9: cluster 0 allows stride 4, cluster 1 stride 2 (3 > 2.5), together stride 2;
    # cluster 2, nearer (a pixel of depth 4 = 4/9 of depth 9's), allows 0.5 / (4/9) = 1.1 px: stride 8.
    assert strides(2.5, [0, 2, 3]) == [1, 3]
    assert strides(0.0, [0, 1, 3]) == [0, 0]
    assert strides(100.0, [0, 3]) == [4]
    # Just under and over a threshold: cluster 0's stride 8 deviates by exactly 4 pixels at depth 9.
    assert strides(4.0 * 1.001, [0, 1, 3])[0] == 3 and strides(4.0 * 0.999, [0, 1, 3])[0] == 2
    # A model scaled 2x doubles every deviation and the spheres (nearest depth 20 - 2 = 18): 4 px again.
    scaled = np.diag([2.0, 2.0, 2.0, 1.0])
    assert strides(4.0 * 2.0 * 9.0 / 18.0 * 1.001, [0, 1, 3], model_view=scaled)[0] == 3
    assert strides(4.0 * 2.0 * 9.0 / 18.0 * 0.999, [0, 1, 3], model_view=scaled)[0] == 2
    # A sphere reaching the eye, or not finite, keeps every point; so does an infinite deviation.
    at_eye = bounds.copy()
    at_eye[1, 3] = 10.5
    assert strides(100.0, [0, 1, 2, 3], cluster_bounds=at_eye) == [4, 0, 4]
    not_finite = bounds.copy()
    not_finite[0, 2] = np.nan
    assert strides(100.0, [0, 1, 3], cluster_bounds=not_finite) == [0, 4]
    # Orthographic: one pixel size everywhere (2 / (P[1][1] x 500) units).
    orthographic = np.diag([0.1, 0.1, -0.02, 1.0])
    ortho_pixel = 2.0 / (0.1 * 500)
    assert strides(4.0 * _pixel(9.0) / ortho_pixel * 1.001, [0, 1, 3], projection=orthographic)[0] == 3
    np.testing.assert_array_equal(preview_buffers.cluster_strides([1, 3], [0, 2, 3]), [2, 2, 8])
    with pytest.raises(ValueError, match="tolerance_px"):
        strides(-1.0, [0, 3])
    with pytest.raises(ValueError, match="block_first"):
        strides(1.0, [0, 2])


@pytest.mark.parametrize("distance", [0.8, 3.0, 12.0])
def test_strided_strands_draw_the_chords_spanning_the_selected_segments(real_asset, distance):
    # Brute force from the selection's own strand segments (ViewSelection.indices): per strand, the
    # chords at its cluster's stride that hold a selected segment, once each.
    asset, _, first = real_asset
    n_c = asset.control_points
    view_selection = asset.view_selection()
    projection = perspective(np.radians(40), 16 / 9, 0.01, 100.0)
    view_selection.update(look_at(np.array([0.0, -distance, 0.5]), np.zeros(3)), projection, (1280, 720), 2.0)
    selected = view_selection.indices(len(asset.levels), "lines").reshape(-1, 2).astype(np.int64)
    assert len(selected) > 0
    strand_cluster = np.repeat(np.arange(asset.cluster_count), np.diff(first))
    rng = np.random.default_rng(4)
    for strides in (np.ones(asset.cluster_count, np.int32), rng.choice(STRIDES, asset.cluster_count).astype(np.int32)):
        items, k = np.divmod(selected[:, 0], n_c)
        stride = strides[strand_cluster[items]]
        start = k // stride * stride
        expected = {(item * n_c + a, item * n_c + min(a + s, n_c - 1)) for item, a, s in zip(items, start, stride)}
        lines = view_selection.strided_strand_lines(strides)
        assert lines.dtype == np.uint32 and lines.shape[1] == 2
        assert len(lines) == len(expected) and {tuple(line) for line in lines.tolist()} == expected
        assert view_selection.strided_strand_segments(strides) == len(expected)
    # Every stride 1: exactly the selected segments.
    ones = np.ones(asset.cluster_count, np.int32)
    assert view_selection.strided_strand_segments(ones) == view_selection.segments_per_level()[len(asset.levels)]
    lines = view_selection.strided_strand_lines(ones).astype(np.int64)
    np.testing.assert_array_equal(lines[np.lexsort(lines.T[::-1])], selected[np.lexsort(selected.T[::-1])])
    with pytest.raises(ValueError, match="one stride per L0 cluster"):
        view_selection.strided_strand_lines(ones[:-1])
    with pytest.raises(ValueError, match="strides must be >= 1"):
        view_selection.strided_strand_segments(ones * 0)


def test_real_hair_far_view_draws_ten_times_fewer_segments_than_its_strands(real_hair, real_asset):
    # Issue 14's target on the real hairstyle: the far view (25x the hair's size, 1280 x 720, eps_w =
    # 2 px) in the preview's own count: thick hairs selected plus the strands' chords drawn.
    asset, points, first = real_asset
    strands = len(asset.levels)
    n_c = asset.control_points
    lower, upper = real_hair.bounding_box()
    centre, size = (lower + upper) / 2, float(np.linalg.norm(upper - lower))
    projection = perspective(np.radians(40), 1280 / 720, 0.01 * size, 100 * size)
    view = look_at(centre + np.array([0.0, -25.0 * size, 0.2 * size]), centre)
    view_selection = asset.view_selection()
    view_selection.update(view, projection, (1280, 720), 2.0)
    bounds = preview_buffers.cluster_blocks(first, n_c, preview_buffers.BLOCK_SEGMENTS)
    deviation = preview_buffers.stride_deviation(points, n_c, first)
    cluster_bounds = asset.frame_skinning().selection_geometry()["cluster_bounds"]

    def drawn(tolerance_px):
        block = preview_buffers.view_block_strides(deviation, cluster_bounds, view, projection, (1280, 720), tolerance_px,
                                                   bounds)
        segments = view_selection.segments_per_level()
        segments[strands] = view_selection.strided_strand_segments(preview_buffers.cluster_strides(block, bounds))
        return int(segments.sum())

    every_strand = real_hair.point_count - len(real_hair)
    assert every_strand / drawn(preview_buffers.PREVIEW_VERTEX_TOLERANCE_PX) >= 10.0
    assert every_strand / drawn(0.0) < 5.0  # the selection alone is far from it
    # Every chord stays within the tolerance of the points it skips, a pixel taken at the cluster's
    # nearest depth (brute force over the clusters' spheres in view space).
    tolerance = preview_buffers.PREVIEW_VERTEX_TOLERANCE_PX
    block = preview_buffers.view_block_strides(deviation, cluster_bounds, view, projection, (1280, 720), tolerance,
                                               bounds)
    assert np.asarray(STRIDES)[block].max() > 1
    centres = cluster_bounds[:, :3].astype(np.float64) @ view[:3, :3].T + view[:3, 3]
    nearest = -centres[:, 2] - cluster_bounds[:, 3]
    pixel = 2.0 * nearest * np.tan(np.radians(20)) / 720
    stride_index = np.repeat(block, np.diff(bounds))
    assert np.all(deviation[np.arange(asset.cluster_count), stride_index] <= tolerance * pixel * (1 + 1e-4))
