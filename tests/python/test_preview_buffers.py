"""Vertex layouts of the viewport LoD preview and the per-view selection they are drawn with."""

import numpy as np
import pytest

import hairlod
from hairlod import lod, preview_buffers
from hairlod.camera import look_at, perspective


@pytest.fixture(scope="module")
def asset_and_strands():
    rng = np.random.default_rng(5)
    roots = rng.normal(size=(600, 3))
    roots /= np.linalg.norm(roots, axis=1, keepdims=True)
    steps = np.linspace(0.0, 1.0, 8)[None, :, None]
    points = roots[:, None, :] * (1.0 + 0.05 * steps) - 0.4 * steps * np.array([0.0, 0.0, 1.0])
    strands = hairlod.Strands.from_counts(points.reshape(-1, 3).astype(np.float32), np.full(600, 8),
                                          np.full(600 * 8, 0.003, np.float32))
    return lod.build_lod(strands, guides=10, levels=4, control_points=6, seed=2), strands


def test_polyline_tangents_are_unit_and_follow_the_curve():
    points = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 0]]], np.float32)
    tangents = preview_buffers.polyline_tangents(points)
    np.testing.assert_allclose(np.linalg.norm(tangents, axis=2), 1.0, rtol=1e-6)
    np.testing.assert_allclose(tangents[0, 0], [1, 0, 0])
    np.testing.assert_allclose(tangents[0, 1], np.array([1, 1, 0]) / np.sqrt(2), rtol=1e-6)
    # The last stretch has zero length: a fixed unit tangent, not NaN.
    np.testing.assert_allclose(tangents[0, 3], [0, 0, 1])
    with pytest.raises(ValueError, match="points must have shape"):
        preview_buffers.polyline_tangents(np.zeros((3, 1, 3)))


def test_thick_strip_vertices_duplicate_each_control_point(asset_and_strands):
    asset, _ = asset_and_strands
    geometry = asset.skin(asset.rest_guides)
    level, geometry_level = asset.levels[1], geometry["levels"][1]
    arrays = preview_buffers.thick_strip_vertices(geometry_level, level.n_total, level.density)
    hairs, control_points = level.centres.shape[:2]
    for name in ("position", "tangent", "major", "minor", "cluster"):
        assert arrays[name].shape[0] == 2 * hairs * control_points and arrays[name].dtype == np.float32
        np.testing.assert_array_equal(arrays[name][0::2], arrays[name][1::2])
    np.testing.assert_allclose(arrays["position"][0::2].reshape(hairs, control_points, 3), geometry_level["centres"])
    np.testing.assert_array_equal(arrays["cluster"][0::2, 0].reshape(hairs, control_points)[:, 0], level.n_total)


def test_strand_lines_follow_the_hierarchy_order(asset_and_strands):
    asset, _ = asset_and_strands
    rest = asset.skin(asset.rest_guides)["strands"]
    order = asset.arrays()["strand_order"]
    arrays = preview_buffers.strand_line_vertices(rest, order, asset.control_points)
    n_c = asset.control_points
    np.testing.assert_array_equal(arrays["position"][:n_c], rest.points[order[0] * n_c:(order[0] + 1) * n_c])
    with pytest.raises(ValueError, match="expected"):
        preview_buffers.strand_line_vertices(rest, order[:-1], n_c)


def test_view_selection_indices_address_the_vertex_buffers(asset_and_strands):
    asset, strands = asset_and_strands
    view_selection = asset.view_selection()
    lower, upper = strands.bounding_box()
    centre, size = (lower + upper) / 2, float(np.linalg.norm(upper - lower))
    projection = perspective(np.radians(40), 16 / 9, 0.01 * size, 100 * size)
    for distance in (0.8, 4.0, 40.0):
        view_selection.reset()
        view = look_at(centre + np.array([0.0, -distance * size, 0.2 * size]), centre)
        assert view_selection.update(view, projection, (1280, 720), 2.0)
        segments = view_selection.segments_per_level()
        assert len(segments) == len(asset.levels) + 1
        for level in range(view_selection.level_count):
            items = len(asset.levels[level].n_total) if level < len(asset.levels) else asset.strand_count
            strips = view_selection.indices(level, "strips")
            lines = view_selection.indices(level, "lines")
            assert strips.size == 6 * segments[level] and lines.size == 2 * segments[level]
            if strips.size:
                assert strips.max() < 2 * items * asset.control_points
    with pytest.raises(ValueError, match="primitive"):
        view_selection.indices(0, "points")


def test_selection_keys_name_each_vertex_cluster_and_point(asset_and_strands):
    asset, _ = asset_and_strands
    n_c = asset.control_points
    for level in range(len(asset.levels) + 1):
        first = preview_buffers.cluster_items(asset, level)
        items = len(asset.levels[level].n_total) if level < len(asset.levels) else asset.strand_count
        assert first[0] == 0 and first[-1] == items and len(first) == asset.cluster_count + 1
        per_point = 2 if level < len(asset.levels) else 1
        keys = preview_buffers.selection_keys(first, n_c, per_point)
        assert keys.shape == (items * n_c * per_point, 2) and keys.dtype == np.float32
        item = np.arange(len(keys)) // (n_c * per_point)
        np.testing.assert_array_equal(keys[:, 1], (np.arange(len(keys)) // per_point) % n_c)
        np.testing.assert_array_equal(keys[:, 0], np.searchsorted(first, item, side="right") - 1)


def test_blocks_cover_every_segment_once_in_the_selection_index_layout(asset_and_strands):
    asset, strands = asset_and_strands
    n_c = asset.control_points
    view_selection = asset.view_selection()
    lower, upper = strands.bounding_box()
    centre, size = (lower + upper) / 2, float(np.linalg.norm(upper - lower))
    view_selection.update(look_at(centre + np.array([0.0, -4.0 * size, 0.2 * size]), centre),
                          perspective(np.radians(40), 16 / 9, 0.01 * size, 100 * size), (1280, 720), 2.0)
    selection = view_selection.selection
    for level in range(view_selection.level_count):
        primitive = "strips" if level < len(asset.levels) else "lines"
        first = preview_buffers.cluster_items(asset, level)
        bounds = preview_buffers.cluster_blocks(first, n_c, max_segments=7 * (n_c - 1))
        assert bounds[0] == 0 and bounds[-1] == asset.cluster_count and np.all(np.diff(bounds) > 0)
        blocks = [preview_buffers.block_indices(first, a, b, n_c, primitive) for a, b in zip(bounds[:-1], bounds[1:])]
        every = np.concatenate(blocks).reshape(-1)
        # Every segment of the level once: the selection's own indices are a subset of the same elements.
        width = 6 if primitive == "strips" else 2
        assert every.size == width * first[-1] * (n_c - 1)
        elements = {tuple(e) for e in every.reshape(-1, width)}
        assert len(elements) == first[-1] * (n_c - 1)
        selected = view_selection.indices(level, primitive).reshape(-1, width)
        assert all(tuple(e) in elements for e in selected)
        # A block is drawn exactly when the selection puts one of its visible segments at this level.
        texture, present = view_selection.frame_levels()
        np.testing.assert_array_equal(texture, np.where(selection.visible[:, None], selection.levels, -1))
        to_draw = preview_buffers.blocks_to_draw(present[:, level], bounds)
        for block, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
            wanted = ((selection.levels[a:b] == level) & selection.visible[a:b, None]).any()
            assert to_draw[block] == wanted
    with pytest.raises(ValueError, match="primitive"):
        preview_buffers.block_indices(first, 0, 1, n_c, "points")
