"""Following animated hair: guides resampled from moved strands, FrameSkinning's maps (the GPU path)
against the CPU skin, selection on moved geometry, and the self-shadowing volume that follows."""

import math

import numpy as np
import pytest

from hairlod import HairlodError, Strands, lod, self_shadow
from hairlod.temporal import bend, turn
from hairlod.lod import build_lod
from test_lod import hanging_hair, look_at, perspective


@pytest.fixture(scope="module")
def hair():
    return hanging_hair(curves=1200, points=12)


@pytest.fixture(scope="module")
def asset(hair):
    return build_lod(hair, guides=16, levels=5, control_points=8, seed=1)


def rigid(points):
    angle = 0.9
    rotation = np.array([[math.cos(angle), 0, math.sin(angle)], [0, 1, 0], [-math.sin(angle), 0, math.cos(angle)]])
    return (np.asarray(points, np.float64) @ rotation.T + (0.5, -2.0, 1.0)).astype(np.float32)


def guide_curves(hair, asset, deform):
    """The guide strands of `hair`, moved by `deform`, as a Blender reader gathers them."""
    offsets = hair.offsets
    pieces = [hair.points[offsets[g]:offsets[g + 1]] for g in asset.guide_strands]
    counts = [len(piece) for piece in pieces]
    return Strands.from_counts(deform(np.concatenate(pieces)), np.array(counts), np.zeros(sum(counts), np.float32))


def test_guides_resampled_from_moved_strands_are_the_moved_rest_guides(hair, asset):
    size = float(np.ptp(asset.rest_guides.reshape(-1, 3), axis=0).max())
    at_rest = asset.resample_guides(guide_curves(hair, asset, lambda p: p))
    assert at_rest.shape == asset.rest_guides.shape
    assert np.abs(at_rest - asset.rest_guides).max() <= 1e-6 * size
    moved = asset.resample_guides(guide_curves(hair, asset, rigid))
    assert np.abs(moved - rigid(asset.rest_guides)).max() <= 1e-5 * size
    with pytest.raises(HairlodError, match="expected 16 guide curves"):
        asset.resample_guides(hanging_hair(curves=3, points=5))


def test_the_rest_pose_is_decoded_not_skinned(asset):
    """skin() and select() without guides use the stored rest pose exactly (what the preview's
    vertex buffers hold); skinning the rest guides gives it up to float rounding."""
    rest = asset.skin()
    np.testing.assert_array_equal(rest["strands"].points, asset.preview_vertices()["rest_strands"].points)
    skinned = asset.skin(asset.rest_guides)
    size = float(np.ptp(rest["strands"].points, axis=0).max())
    np.testing.assert_allclose(skinned["strands"].points, rest["strands"].points, rtol=0, atol=1e-6 * size)
    for level, skinned_level in zip(rest["levels"], skinned["levels"]):
        np.testing.assert_allclose(skinned_level["centres"], level["centres"], rtol=0, atol=1e-6 * size)
    view = look_at((4, 0.5, 0), (0, 0, -0.3)).astype(np.float32)
    projection = perspective(math.radians(40), 1.5, 0.05, 100).astype(np.float32)
    at_rest = asset.select(view, projection, (900.0, 600.0)).levels
    assert np.mean(at_rest == asset.select(view, projection, (900.0, 600.0), guides=asset.rest_guides).levels) >= 0.999
    per_view = asset.view_selection()
    per_view.update(view, projection, (900.0, 600.0))
    np.testing.assert_array_equal(per_view.selection.levels, at_rest)


def test_maps_applied_to_the_rest_pose_equal_the_cpu_skin(asset):
    """What skinning.glsl computes (maps on the rest vertex buffers) is LodAsset.skin, rigid or not."""
    rest = asset.skin(asset.rest_guides)
    skinning = asset.frame_skinning()
    maps = skinning.maps
    assert maps.shape == (asset.cluster_count, 8, lod.SKIN_MAP_TEXELS, 4)
    # At rest each map is the identity about its rest origin: no second-order terms.
    assert np.abs(maps[..., 1:4, :3] - np.eye(3)).max() <= 1e-6
    assert np.array_equal(maps[..., 1:4, 3], maps[..., 0, :3])
    assert not maps[..., 4:, :].any() and not maps[..., 0, 3].any()
    rest_points = rest["strands"].points.reshape(-1, 8, 3).astype(np.float64)
    cluster = asset.levels[0].membership
    kept = np.full_like(maps, np.nan)
    for deform in (rigid, lambda p: bend(p, 0.5), lambda p: turn(bend(p, 0.3), 1.0)):
        guides = deform(asset.rest_guides)
        skinning.update(guides)
        gpu = lod.apply_maps(skinning.maps[cluster], rest_points)
        np.testing.assert_array_equal(skinning.maps_into(kept), skinning.maps)  # into an array kept from frame to frame
        cpu = asset.skin(guides)["strands"].points.reshape(-1, 8, 3)
        assert np.abs(gpu - cpu).max() <= 2e-6 * np.abs(cpu).max()


def test_maps_into_takes_only_an_array_it_can_write_as_it_is(asset):
    skinning = asset.frame_skinning()
    shape = skinning.maps.shape
    for bad in (np.zeros(shape, np.float64), np.zeros(shape[:-1] + (3,), np.float32),
                np.zeros(shape[:-1] + (8,), np.float32)[..., ::2]):
        with pytest.raises(ValueError, match=r"out must be a writeable, C-contiguous float32 array of shape \[" +
                           ", ".join(map(str, shape)) + r"\]"):
            skinning.maps_into(bad)
    read_only = np.zeros(shape, np.float32)
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match="writeable"):
        skinning.maps_into(read_only)


def test_selection_follows_the_skinned_geometry(asset):
    skinning = asset.frame_skinning()
    selection = asset.view_selection(skinning=skinning)
    view = look_at((4, 0.5, 0), (0, 0, -0.3)).astype(np.float32)
    projection = perspective(math.radians(40), 1.5, 0.05, 100).astype(np.float32)
    selection.update(view, projection, (900.0, 600.0))
    visible = selection.selection.visible.copy()
    assert visible.all()
    # The hair moves far to one side: its clusters leave the view, as the moved geometry says.
    skinning.update(asset.rest_guides + np.float32((0.0, 50.0, 0.0)))
    selection.set_geometry(skinning)
    assert selection.update(view, projection, (900.0, 600.0))
    assert not selection.selection.visible.any()
    bounds = skinning.selection_geometry()["cluster_bounds"]
    assert bounds.shape == (asset.cluster_count, 4) and np.all(bounds[:, 1] > 45.0)
    np.testing.assert_array_equal(skinning.cluster_bounds, bounds)  # the same spheres, alone
    # A translation keeps every width ellipsoid; at rest each holds its level's semi-axes there.
    nc = asset.control_points
    for level, (ellipsoids, hairs) in enumerate(zip(skinning.selection_geometry()["width_ellipsoid"],
                                                    asset.skin(None)["levels"])):
        assert ellipsoids.shape == (asset.cluster_count, nc, 6)
        xx, yy, zz, xy, yz, zx = np.moveaxis(ellipsoids.astype(np.float64), -1, 0)
        matrices = np.stack([np.stack([xx, xy, zx], -1), np.stack([xy, yy, yz], -1), np.stack([zx, yz, zz], -1)], -2)
        cluster_first = asset.arrays()["levels"][level]["cluster_first"]
        cluster = np.repeat(np.arange(asset.cluster_count), np.diff(cluster_first))
        inverse = np.linalg.inv(matrices)[cluster]  # [hairs, n_c, 3, 3]
        for axis in ("major", "minor"):
            x = hairs[axis] - (hairs[axis] * hairs["tangents"]).sum(-1, keepdims=True) * hairs["tangents"]
            assert np.einsum("hki,hkij,hkj->hk", x, inverse, x).max() <= 1.0 + 1e-3
    with pytest.raises(HairlodError, match="deformed guides must have shape"):
        skinning.update(asset.rest_guides[:3])
    nan = asset.rest_guides.copy()
    nan[2, 3, 1] = np.nan
    with pytest.raises(HairlodError, match="NaN or infinite"):
        skinning.update(nan)
    assert np.all(skinning.selection_geometry()["cluster_bounds"][:, 1] > 45.0)  # the last frame is kept


def test_moved_volume_follows_the_box():
    volume = self_shadow.HairVolume(centre=np.array([1.0, 2.0, 3.0]), semi_axes=np.array([1.0, 2.0, 0.5]), extinction=4.0)
    box = (np.array([0.0, 0.0, 2.5]), np.array([2.0, 4.0, 3.5]))
    same = self_shadow.moved_volume(volume, box, box)
    assert np.allclose(same.centre, volume.centre) and np.allclose(same.semi_axes, volume.semi_axes)
    assert same.extinction == pytest.approx(4.0)
    shifted = self_shadow.moved_volume(volume, box, (box[0] + 5.0, box[1] + 5.0))
    assert np.allclose(shifted.centre, volume.centre + 5.0) and shifted.extinction == pytest.approx(4.0)
    wider = self_shadow.moved_volume(volume, box, (box[0], box[1] + (2.0, 0.0, 0.0)))
    assert np.allclose(wider.semi_axes, (2.0, 2.0, 0.5)) and wider.extinction == pytest.approx(2.0)
    flat = self_shadow.moved_volume(volume, box, (box[0], (2.0, 4.0, 2.5)))
    assert np.isfinite(flat.extinction) and flat.extinction > 0.0


def test_guide_animation_is_stored_with_the_asset_and_read_back(asset, tmp_path):
    from hairlod import lod

    frames = [1, 2, 5]
    guides = np.stack([turn(asset.rest_guides, angle) for angle in (0.0, 0.2, 0.5)])
    manifest = lod.save(asset, tmp_path / "lod", animation=(frames, guides))
    assert manifest["animation"]["frames"] == frames and manifest["animation"]["shape"] == list(guides.shape)
    assert "LodAsset.skin(guides[f])" in manifest["animation"]["meaning"]
    loaded = lod.load(tmp_path / "lod")
    read_frames, read_guides = lod.load_animation(tmp_path / "lod", loaded)
    assert read_frames.tolist() == frames and np.array_equal(read_guides, guides)
    # What an engine does with frame 5: skin everything to its guides.
    moved = loaded.skin(read_guides[2])["strands"].points
    assert np.abs(moved - turn(loaded.skin(loaded.rest_guides)["strands"].points, 0.5)).max() <= 1e-5 * np.abs(moved).max()

    lod.save(asset, tmp_path / "still")
    assert lod.load_animation(tmp_path / "still", asset) is None


@pytest.mark.parametrize("frames, guides, message", [
    ([1, 1], 2, "strictly increasing"),
    ([], 0, "non-empty list of integers"),
    ([0.5], 1, "non-empty list of integers"),
    ([1, 2], 3, r"must have shape \[2, 16, 8, 3\]"),
    ([1], "nan", "NaN or infinite"),
])
def test_bad_guide_animations_are_refused_before_anything_is_written(asset, tmp_path, frames, guides, message):
    from hairlod import lod

    if guides == "nan":
        guides = asset.rest_guides[None].copy()
        guides[0, 3, 2, 1] = np.nan
    else:
        guides = np.repeat(asset.rest_guides[None], guides, axis=0)
    with pytest.raises(ValueError, match=message):
        lod.save(asset, tmp_path / "lod", animation=(frames, guides))
    assert not (tmp_path / "lod").exists()


def test_a_damaged_guide_animation_is_reported(asset, tmp_path):
    from hairlod import lod

    lod.save(asset, tmp_path / "lod", animation=([3, 4], np.stack([asset.rest_guides] * 2)))
    np.save(tmp_path / "lod" / "guide_animation.npy", np.zeros((2, 3), np.float32))
    with pytest.raises(ValueError, match="guide_animation does not match its manifest"):
        lod.load_animation(tmp_path / "lod", asset)


def test_skinned_thick_hairs_keep_the_strands_that_pass_through_them(asset):
    # Counted where each strand crosses each section's plane, the thick hairs hold most of their
    # strands at rest (their sections are fitted there), and skinned to a bend most of their skinned
    # strands: the maps move both by the same field, but a section at control point k follows map k
    # while its members cross it on neighbouring segments, which their own maps move (on this small
    # asset of 16 guides and 8 control points a 0.6 rad bend loses up to 0.15; bench skinning's 100k
    # strands lose up to 0.09 on their finest level at 0.4 rad).
    from hairlod.thick_hair_check import strands_through_sections

    def through(geometry):
        points = geometry["strands"].points.reshape(asset.strand_count, asset.control_points, 3)
        return [strands_through_sections(g["centres"], g["major"], g["minor"], level.membership, points)
                for level, g in zip(asset.levels, geometry["levels"])]

    rest, bent = asset.skin(asset.rest_guides), asset.skin(bend(asset.rest_guides, 0.6))
    assert len(asset.levels) > 0
    for level, (at_rest, skinned) in enumerate(zip(through(rest), through(bent))):
        assert at_rest > 0.75, f"level {level}: {at_rest:.3f} at rest"
        assert skinned > 0.65 and skinned > at_rest - 0.2, f"level {level}: {skinned:.3f} bent against {at_rest:.3f} at rest"


def test_strands_through_sections_are_counted_where_they_cross_the_plane():
    # One hair of 3 sections along z, unit circles in planes tilted 45 degrees about y (axes (1, 0, 1) /
    # sqrt 2 and y, the centres on the z axis). Strand 0 runs up x = 0.5: it crosses every tilted plane
    # at z = c - 0.5, 0.5 / cos 45 = 0.71 from the centre along the axis: inside. Strand 1 up x = 0.9
    # crosses 1.27 from the centre: outside, although its points at the sections' heights project
    # onto the planes 0.64 from the centres (inside by the build's measure).
    from hairlod.thick_hair_check import strands_through_sections

    z = np.array([0.0, 1.0, 2.0])
    centres = np.stack([np.zeros(3), np.zeros(3), z], axis=1)[None]
    major = np.tile(np.array([1.0, 0.0, 1.0]) / math.sqrt(2.0), (1, 3, 1))
    minor = np.tile([0.0, 1.0, 0.0], (1, 3, 1))
    heights = np.linspace(-1.0, 3.0, 3)  # the strands' own points need not be at the sections' heights
    strands = np.stack([np.stack([np.full(3, x), np.zeros(3), heights], axis=1) for x in (0.5, 0.9)])
    # The strands run from z = -1 to 3, so every plane meets them (at z = c - x).
    assert strands_through_sections(centres, major, minor, np.array([0, 0]), strands) == pytest.approx(0.5)
    assert strands_through_sections(centres, major, minor, np.array([0]), strands[:1]) == 1.0
    # A strand that never reaches a section's plane is outside there.
    short = np.stack([np.zeros(3), np.zeros(3), [1.8, 1.9, 2.0]], axis=1)[None]
    assert strands_through_sections(centres, major, minor, np.array([0]), short) == pytest.approx(1.0 / 3.0)
