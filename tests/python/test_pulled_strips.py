"""The layout a sparse thick level is drawn from without per-frame index lists (hairlod.pulled_strips):
what the pulled shader fetches must be the strips ViewSelection.indices draws."""

import numpy as np
import pytest

from hairlod import pulled_strips
from hairlod.camera import look_at, perspective


def _views(strands):
    lower, upper = strands.bounding_box()
    centre, size = (lower + upper) / 2, float(np.linalg.norm(upper - lower))
    projection = perspective(np.radians(40), 16 / 9, 0.01 * size, 100 * size)
    for distance in (0.8, 3.0, 12.0, 40.0):
        yield look_at(centre + np.array([0.0, -distance * size, 0.2 * size]), centre), projection


def test_pulled_slots_draw_the_strips_of_the_selected_segments(sphere_hair_lod):
    """Slot s of a batch drawing the segments starting at `starts` makes vertex 4s + 2c + side control
    point starts[s] + c, side `side`: strip vertex 2 (starts[s] + c) + side, so its triangles are the
    strips' own, in the same order."""
    asset, strands = sphere_hair_lod
    selection = asset.view_selection()
    checked = 0
    for view, projection in _views(strands):
        selection.reset()
        selection.update(view, projection, (1280, 720), 2.0)
        for level in range(len(asset.levels)):
            starts = selection.indices(level, "segments")
            strips = selection.indices(level, "strips")
            assert starts.dtype == np.uint32 and starts.size == selection.segments_per_level()[level]
            if not starts.size:
                continue
            capacity = pulled_strips.slot_capacity(starts.size)
            elements = pulled_strips.slot_elements(capacity)
            assert elements.shape == (2 * capacity, 3) and elements.dtype == np.int32
            used = elements[:2 * starts.size].ravel()
            np.testing.assert_array_equal(2 * starts.astype(np.int64)[used // 4] + used % 4, strips)
            # The texture holds the starts, row by row, the rest zeros.
            texels = pulled_strips.segment_texels(starts)
            assert texels.shape[1:] == (pulled_strips.SEGMENT_ROW, 2) and texels.dtype == np.float32
            pairs = texels.reshape(-1, 2).astype(np.int64)
            np.testing.assert_array_equal(pairs[:starts.size, 0] + (pairs[:starts.size, 1] << 16), starts)
            assert not pairs[starts.size:].any()
            # Written into memory kept from frame to frame (as the viewport does): the same texels where
            # the starts are, that memory's own past them.
            rows = pulled_strips.texel_rows(starts.size)
            kept = np.full(((rows + 1) * pulled_strips.SEGMENT_ROW, 2), -7.0, np.float32)
            into = pulled_strips.segment_texels(starts, out=kept)
            assert np.shares_memory(into, kept) and into.shape == texels.shape
            np.testing.assert_array_equal(into.reshape(-1, 2)[:starts.size], texels.reshape(-1, 2)[:starts.size])
            assert (kept[starts.size:] == -7.0).all()
            checked += 1
    assert checked >= 3  # several views select some thick level


def test_points_texture_holds_each_control_points_strip_attributes(sphere_hair_lod):
    asset, _ = sphere_hair_lod
    for arrays in asset.preview_vertices()["levels"]:
        texels = pulled_strips.point_texels(arrays)
        points = len(arrays["position"]) // 2
        assert texels.dtype == np.float32 and texels.shape[1:] == (pulled_strips.POINT_ROW * pulled_strips.POINT_TEXELS, 4)
        assert texels.shape[0] == -(-points // pulled_strips.POINT_ROW)
        per_point = texels.reshape(-1, 4 * pulled_strips.POINT_TEXELS)
        # What thick_hair.vert.glsl reads: t0.xyz, (t0.w, t1.xy), (t1.zw, t2.x), t2.yzw, t3.xy, t3.zw.
        fields = {"position": per_point[:, 0:3], "tangent": per_point[:, 3:6], "major": per_point[:, 6:9],
                  "minor": per_point[:, 9:12], "cluster": per_point[:, 12:14], "select_key": per_point[:, 14:16]}
        for name, values in fields.items():
            np.testing.assert_array_equal(values[:points], arrays[name][0::2], err_msg=name)
            np.testing.assert_array_equal(arrays[name][0::2], arrays[name][1::2], err_msg=name)
        assert not per_point[points:].any()


def test_slot_capacities_grow_by_at_most_sqrt_2():
    previous = 0
    for segments in [0, 1, 255, 256, 257, 1000, 4097, 65536, 110000, 3_000_000]:
        capacity = pulled_strips.slot_capacity(segments)
        assert capacity >= max(segments, pulled_strips.MIN_SLOTS) and capacity % 2 == 0 and capacity >= previous
        if segments > pulled_strips.MIN_SLOTS:
            assert capacity <= np.sqrt(2.0) * segments + 2
        previous = capacity
    capacities = {pulled_strips.slot_capacity(n) for n in range(0, 20000, 7)}
    assert len(capacities) <= 14  # a batch per capacity, so few batches however the selection moves


def test_bad_layouts_are_clear_errors(sphere_hair_lod):
    asset, _ = sphere_hair_lod
    arrays = dict(asset.preview_vertices()["levels"][0])
    with pytest.raises(ValueError, match="segments must be >= 0"):
        pulled_strips.slot_capacity(-1)
    with pytest.raises(ValueError, match="one-dimensional"):
        pulled_strips.segment_texels(np.zeros((2, 2), np.uint32))
    with pytest.raises(ValueError, match="unsigned 32-bit"):
        pulled_strips.segment_texels(np.array([2**32], np.int64))
    with pytest.raises(ValueError, match="unsigned 32-bit"):
        pulled_strips.segment_texels(np.array([-1], np.int64))
    # Every unsigned 32-bit start comes back exactly from its halves, whatever its integer type.
    for starts in (np.array([0, 65535, 65536, 2**24 + 1, 2**32 - 1], np.uint32), np.array([2**31 + 3], np.int64)):
        low, high = pulled_strips.segment_texels(starts).reshape(-1, 2)[:len(starts)].astype(np.int64).T
        np.testing.assert_array_equal(low + (high << 16), starts)
    assert [pulled_strips.texel_rows(n) for n in (0, 1, pulled_strips.SEGMENT_ROW, pulled_strips.SEGMENT_ROW + 1)] == [1, 1, 1, 2]
    too_small = np.zeros((pulled_strips.SEGMENT_ROW - 1, 2), np.float32)
    with pytest.raises(ValueError, match="need 4096"):
        pulled_strips.segment_texels(np.arange(3, dtype=np.uint32), out=too_small)
    for wrong in (np.zeros((pulled_strips.SEGMENT_ROW, 2), np.float64), np.zeros((2, pulled_strips.SEGMENT_ROW), np.float32).T,
                  np.zeros(2 * pulled_strips.SEGMENT_ROW, np.float32)):
        with pytest.raises(ValueError, match="C-contiguous float32"):
            pulled_strips.segment_texels(np.arange(3, dtype=np.uint32), out=wrong)
    odd = {name: values[:-1] for name, values in arrays.items()}
    with pytest.raises(ValueError, match="two vertices per control point"):
        pulled_strips.point_texels(odd)
    arrays["major"] = arrays["major"][:, :2]
    with pytest.raises(ValueError, match="'major' has shape"):
        pulled_strips.point_texels(arrays)
