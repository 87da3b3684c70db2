"""Vertex LoD of the drawn strands (lod/vertex_lod.h through render.lod_geometry): what it keeps is a
subset of the selection's control points with every strand's ends, thick hairs keep every section, it is
what makes the far view of the real hair 10x cheaper than its strands at 256 px, and the hair covers
the image as before.
Fixed seeds; tolerances stated per test. Never times."""

import numpy as np
import pytest

from hairlod import _core, cli, lod, render


@pytest.fixture(scope="module")
def asset(real_hair):
    return lod.build_lod(real_hair)


def segments(strands, hairs):
    strand_segments = 0 if strands is None else strands.point_count - strands.curve_count
    thick_segments = 0 if hairs is None else len(hairs["centres"]) - (len(hairs["offsets"]) - 1)
    return strand_segments + thick_segments


def curves(points, offsets):
    return [points[offsets[i]:offsets[i + 1]] for i in range(len(offsets) - 1)]


def is_subsequence(kept, every):
    """Whether the rows of `kept` are rows of `every`, in order, with the same first and last row."""
    if len(kept) < 2 or not (np.array_equal(kept[0], every[0]) and np.array_equal(kept[-1], every[-1])):
        return False
    j = 0
    for row in kept:
        while j < len(every) and not np.array_equal(every[j], row):
            j += 1
        if j == len(every):
            return False
    return True


@pytest.mark.parametrize("view", ["near", "far"])
def test_kept_points_are_the_selections_with_their_ends(real_hair, asset, view):
    camera = render.frame_view(real_hair.points, view, 256)
    every_strand, every_hair = render.lod_geometry(asset, camera, vertex_tolerance_px=0)
    strands, hairs = render.lod_geometry(asset, camera)
    assert strands.curve_count == every_strand.curve_count
    for kept, every in zip(curves(strands.points, strands.offsets), curves(every_strand.points, every_strand.offsets)):
        assert is_subsequence(kept, every)
    for name in hairs:
        assert np.array_equal(hairs[name], every_hair[name]), name
    assert segments(strands, hairs) < segments(every_strand, every_hair)


def test_far_view_draws_ten_times_fewer_segments_than_the_strands(real_hair, asset):
    # The target at 256 px: without the vertex LoD the selection draws 3.5x fewer segments than the
    # strands (the coarse thick hairs are wider than 2 px there, so half the strands are drawn); with
    # it 10.4x fewer (the mohawk's strands lie within 0.1 px of straight over most of their length).
    full = real_hair.point_count - real_hair.curve_count
    camera = render.frame_view(real_hair.points, "far", 256)
    assert full / segments(*render.lod_geometry(asset, camera, vertex_tolerance_px=0)) < 5
    assert full / segments(*render.lod_geometry(asset, camera)) >= 10


def test_far_view_covers_the_image_as_every_control_point_does(real_hair, asset):
    # Alpha from the camera (256 spp, the same seed), at the far view where most points are left out
    # (the sparse mohawk covers about 31 pixels' worth there): the total within 3 % of the same
    # selection with every control point (measured -0.1 %; the strands' own total is 2 % above both).
    kept = render.coverage(real_hair, "lod", "far", 256, 256, asset=asset, seed=5)
    every = render.coverage(real_hair, "lod", "far", 256, 256, asset=asset, seed=5, vertex_tolerance_px=0)
    assert every.sum() > 20
    assert abs(kept.sum() / every.sum() - 1.0) < 0.03, (kept.sum(), every.sum())


def test_bad_tolerances_are_refused_by_name(real_hair, asset):
    camera = render.frame_view(real_hair.points, "far", 64)
    for bad in (-0.1, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="tolerance_px"):
            render.lod_geometry(asset, camera, vertex_tolerance_px=bad)
    parser = cli.build_parser()
    with pytest.raises(cli.UsageError, match="--vertex-tolerance-px"):
        parser.parse_args(["render", "in.hair", "--out", "x.png", "--vertex-tolerance-px", "-1"])
    assert parser.parse_args(["bench", "quality", "in.hair", "--vertex-tolerance-px", "0"]).vertex_tolerance_px == 0


def test_the_binding_checks_its_arrays():
    view, projection = np.eye(4, dtype=np.float32), np.eye(4, dtype=np.float32)
    points = np.zeros((4, 3), np.float32)
    with pytest.raises(ValueError, match="extents"):
        _core.vertex_lod_keep(points, np.array([0, 4]), np.zeros((3, 1), np.float32), view, projection, (64, 64))
    with pytest.raises(ValueError, match="offsets"):
        _core.vertex_lod_keep(points, np.array([0, 3]), np.zeros((4, 1), np.float32), view, projection, (64, 64))
