"""Vertex layouts of the viewport LoD preview and the per-view selection they are drawn with."""

import numpy as np
import pytest

import hairlod
from hairlod import lod, preview_buffers
from hairlod.camera import look_at, perspective


def _central_tangents(points):
    """Oracle: unit tangents of polylines [items, n, 3] by central differences, one-sided at the ends,
    (0, 0, 1) for a stretch without length."""
    steps = np.empty_like(points)
    steps[:, 1:-1] = points[:, 2:] - points[:, :-2]
    steps[:, 0] = points[:, 1] - points[:, 0]
    steps[:, -1] = points[:, -1] - points[:, -2]
    length = np.linalg.norm(steps, axis=2, keepdims=True)
    return np.where(length > 1e-30, steps / np.where(length > 1e-30, length, 1.0), np.array([0.0, 0.0, 1.0]))


def test_thick_strip_vertices_duplicate_each_control_point(sphere_hair_lod):
    asset, _ = sphere_hair_lod
    geometry = asset.skin(asset.rest_guides)
    vertices = asset.preview_vertices()
    n_c = asset.control_points
    assert len(vertices["levels"]) == len(asset.levels)
    for index, (level, geometry_level, arrays) in enumerate(zip(asset.levels, geometry["levels"], vertices["levels"])):
        hairs = level.centres.shape[0]
        for name, components in (("position", 3), ("tangent", 3), ("major", 3), ("minor", 3), ("cluster", 2),
                                 ("select_key", 2)):
            assert arrays[name].shape == (2 * hairs * n_c, components) and arrays[name].dtype == np.float32
            np.testing.assert_array_equal(arrays[name][0::2], arrays[name][1::2])
        # skin() at the rest guides goes through the stencils (quadratic_stencil.h): the identity up to
        # float rounding; the preview reads the decoded rest pose itself.
        for name, skinned in (("position", "centres"), ("tangent", "tangents"), ("major", "major"), ("minor", "minor")):
            np.testing.assert_allclose(arrays[name][0::2].reshape(hairs, n_c, 3), geometry_level[skinned], rtol=0, atol=1e-5)
        cluster = arrays["cluster"][0::2].reshape(hairs, n_c, 2)
        np.testing.assert_array_equal(cluster[..., 0], np.repeat(level.n_total[:, None], n_c, axis=1))
        np.testing.assert_array_equal(cluster[..., 1], level.density)
        # Each hair's L0 cluster and control point, from the level's cluster ranges.
        key = arrays["select_key"][0::2].reshape(hairs, n_c, 2)
        first = preview_buffers.cluster_items(asset, index)
        np.testing.assert_array_equal(key[..., 0], np.repeat((np.searchsorted(first, np.arange(hairs), side="right") - 1)[:, None], n_c, axis=1))
        np.testing.assert_array_equal(key[..., 1], np.tile(np.arange(n_c), (hairs, 1)))


def test_strand_lines_follow_the_hierarchy_order(sphere_hair_lod):
    asset, _ = sphere_hair_lod
    vertices = asset.preview_vertices()
    rest = vertices["rest_strands"]  # the decoded rest pose
    order = asset.arrays()["strand_order"]
    n_c = asset.control_points
    lines = vertices["strands"]
    ordered = rest.points.reshape(-1, n_c, 3)[order]
    np.testing.assert_array_equal(lines["position"], ordered.reshape(-1, 3))
    np.testing.assert_allclose(lines["tangent"], _central_tangents(ordered.astype(np.float64)).reshape(-1, 3), atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(lines["tangent"], axis=1), 1.0, rtol=1e-6)
    first = preview_buffers.cluster_items(asset, len(asset.levels))
    strand = np.arange(len(order))
    np.testing.assert_array_equal(lines["select_key"][:, 0], np.repeat(np.searchsorted(first, strand, side="right") - 1, n_c))
    np.testing.assert_array_equal(lines["select_key"][:, 1], np.tile(np.arange(n_c), len(order)))
    # skin() at the rest guides goes through the stencils: the rest pose up to float rounding.
    skinned = asset.skin(asset.rest_guides)["strands"]
    np.testing.assert_allclose(skinned.points, rest.points, rtol=0, atol=1e-5)
    np.testing.assert_array_equal(skinned.radius, rest.radius)


def test_strand_tangents_of_a_stretch_without_length_are_fixed_not_nan():
    # Two strands whose resampled points all coincide with their root: every stretch has no length.
    points = np.zeros((2 * 4, 3), np.float32)
    points[4:] = (1.0, 0.0, 0.0)
    strands = hairlod.Strands.from_counts(points, np.full(2, 4), np.full(8, 0.01, np.float32))
    asset = lod.build_lod(strands, guides=2, levels=2, control_points=4, seed=0)
    tangents = asset.preview_vertices()["strands"]["tangent"]
    np.testing.assert_array_equal(tangents, np.tile([0.0, 0.0, 1.0], (len(tangents), 1)))


def test_view_selection_indices_address_the_vertex_buffers(sphere_hair_lod):
    asset, strands = sphere_hair_lod
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


def test_cluster_items_are_ranges_of_each_level(sphere_hair_lod):
    asset, _ = sphere_hair_lod
    for level in range(len(asset.levels) + 1):
        first = preview_buffers.cluster_items(asset, level)
        items = len(asset.levels[level].n_total) if level < len(asset.levels) else asset.strand_count
        assert first[0] == 0 and first[-1] == items and len(first) == asset.cluster_count + 1
        assert np.all(np.diff(first) >= 0)
    # The strands' ranges are the stored L0 hairs' member ranges taken per cluster.
    stored = asset.arrays()["levels"][0]
    np.testing.assert_array_equal(preview_buffers.cluster_items(asset, len(asset.levels)),
                                  stored["member_first"][stored["cluster_first"]])


def test_blocks_cover_every_segment_once_in_the_selection_index_layout(sphere_hair_lod):
    asset, strands = sphere_hair_lod
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
        texture, present, whole = view_selection.frame_levels()
        np.testing.assert_array_equal(texture, np.where(selection.visible[:, None], selection.levels, -1))
        # A block skips the per-fragment test exactly when every segment of every cluster in it is
        # visible and at this level.
        to_draw, one_level = preview_buffers.level_blocks(present, whole, level, bounds)
        for block, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
            wanted = ((selection.levels[a:b] == level) & selection.visible[a:b, None]).any()
            assert to_draw[block] == wanted
            assert one_level[block] == ((selection.levels[a:b] == level).all() and selection.visible[a:b].all())
            assert to_draw[block] or not one_level[block]
    with pytest.raises(ValueError, match="primitive"):
        preview_buffers.block_indices(first, 0, 1, n_c, "points")


def test_blocks_are_runs_of_the_whole_levels_elements(sphere_hair_lod):
    # The preview cuts one element array of a whole level into its blocks' rows (lod_preview.LevelBlocks).
    asset, _ = sphere_hair_lod
    n_c = asset.control_points
    for level, primitive, rows_per_segment in ((0, "strips", 2), (len(asset.levels), "lines", 1)):
        first = preview_buffers.cluster_items(asset, level)
        bounds = preview_buffers.cluster_blocks(first, n_c, max_segments=5 * (n_c - 1))
        whole = preview_buffers.block_indices(first, 0, len(first) - 1, n_c, primitive)
        row_first = first * (n_c - 1) * rows_per_segment
        for a, b in zip(bounds[:-1], bounds[1:]):
            np.testing.assert_array_equal(whole[row_first[a]:row_first[b]],
                                          preview_buffers.block_indices(first, a, b, n_c, primitive))


def test_blocks_wasteful_counts_the_segments_drawn_but_selected_elsewhere():
    # Blocks of 10, 20 and 30 segments; the level selected 12 of them. Drawing blocks 0 and 2 rasterises
    # 40 segments, 28 of them selected at other levels: more than 2x the 12 selected, within 3x.
    segments = np.array([10, 20, 30])
    to_draw = np.array([True, False, True])
    assert preview_buffers.blocks_wasteful(segments, to_draw, 12, ratio=1.0)
    assert preview_buffers.blocks_wasteful(segments, to_draw, 12, ratio=2.0)
    assert not preview_buffers.blocks_wasteful(segments, to_draw, 12, ratio=3.0)
    # Blocks holding only selected segments waste nothing; nothing drawn wastes nothing.
    assert not preview_buffers.blocks_wasteful(segments, to_draw, 40, ratio=0.0)
    assert not preview_buffers.blocks_wasteful(segments, np.zeros(3, bool), 0, ratio=0.0)
    # Without a ratio, the preview's: 3 selected of 40 drawn waste 37 > 3 x 3 (at its default of 3).
    assert preview_buffers.THICK_WASTE_RATIO == 3.0
    assert preview_buffers.blocks_wasteful(segments, to_draw, 3)
    assert not preview_buffers.blocks_wasteful(segments, to_draw, 12)


def test_blocks_near_to_far_orders_by_view_depth():
    # Three blocks of clusters along the view axis; the camera at z = 10 looks down -z: the block whose
    # clusters' mean centre is nearest (largest z) comes first, whatever the spheres' radii.
    bounds = np.array([0, 2, 3, 5])
    spheres = np.array([[0, 0, -4, 1], [0, 0, -2, 9],   # block 0: mean z -3
                        [5, 0, 6, 0.1],                  # block 1: z 6
                        [0, 1, 0, 2], [0, -1, 2, 2]],    # block 2: mean z 1
                       dtype=np.float32)
    view = look_at(np.array([0.0, 0.0, 10.0]), np.zeros(3), up=(0.0, 1.0, 0.0))
    centres = preview_buffers.block_centres(spheres, bounds)
    np.testing.assert_allclose(centres[:, 2], [-3, 6, 1])
    np.testing.assert_array_equal(preview_buffers.blocks_near_to_far(centres, view), [1, 2, 0])
    # From the other side the order turns round.
    view = look_at(np.array([0.0, 0.0, -10.0]), np.zeros(3), up=(0.0, 1.0, 0.0))
    np.testing.assert_array_equal(preview_buffers.blocks_near_to_far(centres, view), [0, 2, 1])
    assert preview_buffers.block_centres(spheres, np.array([0])).shape == (0, 3)


def test_level_blocks_refuses_arrays_that_do_not_match():
    present, whole = np.ones((4, 2), bool), np.zeros(4, np.int8)
    to_draw, one_level = preview_buffers.level_blocks(present, whole, 0, np.array([0, 1, 4]))
    assert to_draw.tolist() == [True, True] and one_level.tolist() == [True, True]
    with pytest.raises(ValueError, match="block_first"):
        preview_buffers.level_blocks(present, whole, 0, np.array([0, 1, 3]))
    with pytest.raises(ValueError, match="level 2"):
        preview_buffers.level_blocks(present, whole, 2, np.array([0, 4]))
    with pytest.raises(ValueError, match="present"):
        preview_buffers.level_blocks(present[:3], whole, 0, np.array([0, 4]))
