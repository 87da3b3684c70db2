"""hairlod.lod: build, per-level invariants, skinning of rigid motions, selection."""

import json
import math

import numpy as np
import pytest

from hairlod import HairlodError, Strands
from hairlod.lod import build_lod


def hanging_hair(curves=1500, points=10, offset=(0.0, 0.0, 0.0), seed=2):
    rng = np.random.default_rng(seed)
    azimuth = rng.uniform(0, 2 * math.pi, curves)
    polar = rng.uniform(0, 1.4, curves)
    roots = np.stack([np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)], axis=1)
    t = np.linspace(0, 1, points)
    pts = roots[:, None, :] * (1 + 0.2 * t[None, :, None]) + np.stack(
        [0.05 * np.sin(9 * t[None, :] + azimuth[:, None]), np.zeros((curves, points)), -np.broadcast_to(t, (curves, points))],
        axis=2)
    pts = (pts + np.asarray(offset)).astype(np.float32).reshape(-1, 3)
    return Strands.from_counts(pts, np.full(curves, points), np.full(curves * points, 0.002, np.float32))


def look_at(eye, target, up=(0, 0, 1)):
    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fov_y, aspect, near, far):
    f = 1 / math.tan(fov_y / 2)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]])


@pytest.fixture(scope="module")
def asset():
    return build_lod(hanging_hair(), guides=16, levels=5, control_points=8, seed=1)


def test_levels_partition_strands_and_cover(asset):
    assert asset.strand_count == 1500 and asset.guide_count == 16
    assert len(asset.levels) >= 2
    for level in asset.levels:
        assert level.n_total.sum() == 1500
        assert np.array_equal(np.bincount(level.membership, minlength=len(level.n_total)), level.n_total)
        assert level.coverage >= 0.95
        assert np.all(np.isfinite(level.radii)) and np.all(level.radii > 0)
    ratios = asset.area_ratios
    print("area ratios", ratios, "coverage", asset.coverage)
    assert all(1.5 < r < 8.0 for r in ratios)


def test_rigid_motion_skins_exactly(asset):
    rest = asset.skin(asset.rest_guides)
    angle = 0.8
    rotation = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    shift = np.array([1.0, -3.0, 2.0])
    moved = asset.skin(asset.rest_guides @ rotation.T + shift)
    expected = rest["strands"].points @ rotation.T + shift
    scale = np.abs(expected).max()
    assert np.abs(moved["strands"].points - expected).max() <= 1e-5 * scale
    for rest_level, moved_level in zip(rest["levels"], moved["levels"]):
        assert np.abs(moved_level["centres"] - (rest_level["centres"] @ rotation.T + shift)).max() <= 1e-5 * scale


def test_selection_monotone_and_eq16_converges(asset):
    projection = perspective(math.radians(45), 4 / 3, 0.01, 1000)
    direction = np.array([1.0, 0.3, 0.2]) / np.linalg.norm([1.0, 0.3, 0.2])
    target = np.array([0, 0, -0.3])
    previous_levels = None
    for distance in (2.5, 5, 10, 40):
        view = look_at(target + distance * direction, target)
        initial = asset.select(view, projection, (800, 600))
        levels = initial.levels.astype(int)
        visible = initial.visible
        if previous_levels is not None:
            both = visible & previous_visible
            assert np.all(levels[both] <= previous_levels[both])
        state = initial
        for _ in range(len(asset.levels) + 1):
            state = asset.select(view, projection, (800, 600), previous=state)
        assert np.array_equal(state.levels[visible], initial.levels[visible])
        assert initial.draws.shape[1] == 6
        previous_levels, previous_visible = levels, visible


def test_hard_cases_and_errors():
    one = build_lod(hanging_hair(curves=1, points=2), guides=256)
    assert one.guide_count == 1 and one.levels[0].n_total.tolist() == [1]
    few = build_lod(hanging_hair(curves=7), guides=256)
    assert few.guide_count == 7
    huge = build_lod(hanging_hair(curves=200, offset=(1e6, -1e6, 1e6)), guides=8)
    assert all(np.all(np.isfinite(level.radii)) for level in huge.levels)
    bad = hanging_hair(curves=5)
    bad.points[3, 1] = np.nan
    with pytest.raises(ValueError):
        build_lod(bad)
    with pytest.raises(HairlodError):
        build_lod(hanging_hair(curves=5), levels=1)
    with pytest.raises(ValueError):
        few.skin(np.zeros((3, 16, 3)))


def _assert_same_asset(a, b):
    arrays_a, arrays_b = a.arrays(), b.arrays()
    for name in arrays_a:
        if name != "levels":
            assert np.array_equal(arrays_a[name], arrays_b[name]), name
    assert len(arrays_a["levels"]) == len(arrays_b["levels"])
    for level_a, level_b in zip(arrays_a["levels"], arrays_b["levels"]):
        for name in level_a:
            assert np.array_equal(level_a[name], level_b[name]), name
    assert a.scalars() == b.scalars() and a.level_ids == b.level_ids and a.timings == b.timings


def test_save_load_gives_an_identical_asset(asset, tmp_path):
    from hairlod import io, lod

    manifest = lod.save(asset, tmp_path / "asset")
    loaded = lod.load(tmp_path / "asset")
    _assert_same_asset(asset, loaded)
    rest, again = asset.skin(asset.rest_guides), loaded.skin(loaded.rest_guides)
    assert np.array_equal(rest["strands"].points, again["strands"].points)
    for level, level_again in zip(rest["levels"], again["levels"]):
        assert np.array_equal(level["corners"], level_again["corners"])
    view, projection = look_at((6, 2, 1), (0, 0, -0.3)), perspective(math.radians(45), 4 / 3, 0.01, 1000)
    first, second = asset.select(view, projection, (800, 600)), loaded.select(view, projection, (800, 600))
    assert np.array_equal(first.levels, second.levels) and np.array_equal(first.draws, second.draws)
    # One .hair per thick level: the rest centres with thickness = 2 x major radius.
    hairs = io.read(tmp_path / "asset" / manifest["thick_levels"][0]["hair_file"])
    assert np.allclose(hairs.points, asset.levels[0].centres.reshape(-1, 3))
    assert np.allclose(hairs.radius, asset.levels[0].radii[..., 0].reshape(-1))
    # Saving again replaces the folder atomically and leaves no temporary folder behind.
    lod.save(asset, tmp_path / "asset")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["asset"]


def _write_older_format(asset, folder, version):
    """Rewrites the format-4 folder `folder` of `asset` as format `version` (2 or 3) wrote it: the
    compact cross-sections stored beside the other level arrays, no ellipse_coverage."""
    manifest_path = folder / "manifest.json"
    manifest = json.loads(manifest_path.read_text())
    for position, level_arrays in enumerate(asset.arrays()["levels"]):
        for name in ("centre_offset", "major_axis", "minor_axis", "radii"):
            file_name = f"level{position}_{name}.npy"
            np.save(folder / file_name, level_arrays[name])
            manifest["thick_levels"][position]["arrays"][f"level{position}_{name}"] = {
                "file": file_name, "dtype": str(level_arrays[name].dtype), "shape": list(level_arrays[name].shape)}
    manifest.pop("ellipse_coverage", None)
    manifest["format"] = f"hairlod-lod/{version}"
    manifest_path.write_text(json.dumps(manifest))
    return manifest


def test_strand_radius_once_per_strand_and_older_folders_still_load(asset, tmp_path):
    from hairlod import lod

    # The hanging hair's radius is the same along every strand: stored once per strand.
    assert asset.arrays()["strand_radius"].shape == (asset.strand_count,)
    # A tapered hair keeps one radius per control point; written as formats 2 and 3 did (with the
    # cross-sections), it loads back unchanged.
    hair = hanging_hair(curves=300)
    radius = hair.radius.copy()
    radius[hair.offsets[1:] - 1] *= 0.5  # every tip
    tapered = lod.build_lod(Strands(hair.points, hair.offsets, radius), guides=8)
    assert tapered.arrays()["strand_radius"].shape == (tapered.strand_count * tapered.control_points,)
    lod.save(tapered, tmp_path / "tapered")
    manifest = json.loads((tmp_path / "tapered" / "manifest.json").read_text())
    assert manifest["format"] == "hairlod-lod/4"
    assert not any("centre_offset" in name for level in manifest["thick_levels"] for name in level["arrays"])
    for version in (3, 2):
        manifest = _write_older_format(tapered, tmp_path / "tapered", version)
        _assert_same_asset(tapered, lod.load(tmp_path / "tapered"))
    # Sections stored for some levels only are refused, naming the first one missing.
    broken = json.loads(json.dumps(manifest))
    broken["thick_levels"][1]["arrays"] = {name: entry for name, entry in broken["thick_levels"][1]["arrays"].items()
                                           if not name.endswith(("centre_offset", "major_axis", "minor_axis", "radii"))}
    (tmp_path / "tapered" / "manifest.json").write_text(json.dumps(broken))
    with pytest.raises(ValueError, match="level1_centre_offset"):
        lod.load(tmp_path / "tapered")
    manifest["format"] = "hairlod-lod/1"
    (tmp_path / "tapered" / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ValueError, match="format must be one of hairlod-lod/2, hairlod-lod/3, hairlod-lod/4"):
        lod.load(tmp_path / "tapered")


def test_cross_sections_are_fitted_again_on_reading_exactly_as_built(asset, tmp_path):
    from hairlod import lod

    # Format 4 leaves the cross-sections out; reading fits them to the stored strands, bit for bit
    # what the build stored (it fits the same decoded strands), for every level kept.
    for kept in ([0, 1, 2], [0, 2]):
        subset = asset.with_levels(kept)
        again = lod.unpack(lod.pack(subset))
        _assert_same_asset(subset, again)
        assert again.memory_bytes == subset.memory_bytes
    sections = sum(level[name].nbytes for level in asset.arrays()["levels"]
                   for name in ("centre_offset", "major_axis", "minor_axis", "radii"))
    assert asset.stored_bytes == asset.memory_bytes - sections
    manifest = lod.save(asset, tmp_path / "asset")
    assert manifest["stored_bytes"] == asset.stored_bytes and manifest["ellipse_coverage"] == pytest.approx(0.95)
    # A format-4 description without the coverage the sections are fitted with is refused by name.
    del manifest["ellipse_coverage"]
    (tmp_path / "asset" / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ValueError, match="ellipse_coverage"):
        lod.load(tmp_path / "asset")
    manifest["ellipse_coverage"] = 1.5
    (tmp_path / "asset" / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ValueError, match=r"ellipse_coverage must be in \(0, 1\]"):
        lod.load(tmp_path / "asset")


def test_load_rejects_broken_folders(asset, tmp_path):
    from hairlod import lod

    with pytest.raises(ValueError, match="manifest.json"):
        lod.load(tmp_path)
    lod.save(asset, tmp_path / "asset")
    member_first = np.load(tmp_path / "asset" / "level1_member_first.npy")
    np.save(tmp_path / "asset" / "level1_member_first.npy", member_first[::-1].copy())
    with pytest.raises(ValueError, match="member_first"):
        lod.load(tmp_path / "asset")


def test_with_levels_composes_parents(asset):
    kept = asset.with_levels([0, 2])
    assert kept.level_ids == [0, 2]
    expected = asset.levels[1].parent[asset.levels[2].parent]
    assert np.array_equal(kept.levels[1].parent, expected)
    assert np.all(kept.levels[0].parent == -1)
    assert np.array_equal(kept.levels[1].membership, asset.levels[2].membership)


def test_scene_levels_follow_the_cameras(asset):
    from hairlod import lod

    projection = perspective(math.radians(45), 4 / 3, 0.01, 1000)
    near = {"view": look_at((2.5, 0.5, 0.3), (0, 0, -0.3)), "projection": projection, "viewport": (800, 600)}
    far = {"view": look_at((400, 50, 30), (0, 0, -0.3)), "projection": projection, "viewport": (800, 600)}
    near_levels, far_levels = lod.scene_levels(asset, [near]), lod.scene_levels(asset, [far])
    assert max(far_levels) <= min(near_levels) or max(far_levels) < max(near_levels)
    assert lod.scene_levels(asset, [near, far]) == sorted(set(near_levels) | set(far_levels))


def test_levels_about_fourfold_apart_in_area(asset):
    # levels=5 is the most (L0..L3 and the strands); the clusters here (about 90 strands) split
    # about 4x in area per level (Sec. 5.1 step 2) until a split would leave under 4 strands per hair.
    assert 2 <= len(asset.levels) <= 4
    print("mean hair sizes", [level.n_total.mean() for level in asset.levels], "area ratios", asset.area_ratios)
    assert all(2.5 < ratio < 8.0 for ratio in asset.area_ratios)
    assert all(fine.n_total.mean() >= 4.0 for fine in asset.levels)


def test_automatic_guides(tmp_path):
    from hairlod import _core, lod

    hair = hanging_hair(curves=3000)
    assert lod.build_lod(hair, levels=3, control_points=6).guide_count == _core.auto_guide_count(3000) == 23
    assert lod.build_lod(hair, guides=0, levels=3, control_points=6).guide_count == 23
    assert _core.auto_guide_count(100_000) == 256 and _core.auto_guide_count(5) == 5


def test_manifest_states_per_hair_data_and_membership(asset, tmp_path):
    from hairlod import lod

    manifest = lod.save(asset, tmp_path / "asset")
    for position, (level, entry) in enumerate(zip(asset.levels, manifest["thick_levels"])):
        per_hair = entry["per_hair"]
        assert set(per_hair) == {"n_total", "density", "major_axis", "minor_axis", "radii", "membership"}
        assert all(per_hair[name]["meaning"] for name in per_hair)
        arrays = {name: np.load(tmp_path / "asset" / e["file"]) for name, e in per_hair.items()}
        for name, array in arrays.items():
            assert np.array_equal(array, getattr(level, name)), (position, name)
        # Independent checks of the side files: membership agrees with n_total and the parents,
        # the axes are unit and orthogonal, rho follows Sec. 4 from the radii.
        assert np.array_equal(np.bincount(arrays["membership"], minlength=entry["hairs"]), arrays["n_total"])
        assert arrays["n_total"].sum() == asset.strand_count
        if position:
            coarser = np.load(tmp_path / "asset" / manifest["thick_levels"][position - 1]["per_hair"]["membership"]["file"])
            assert np.array_equal(level.parent[arrays["membership"]], coarser)
        assert np.allclose(np.linalg.norm(arrays["major_axis"], axis=2), 1, atol=1e-3)
        assert np.allclose(np.sum(arrays["major_axis"] * arrays["minor_axis"], axis=2), 0, atol=1e-3)
        rho = arrays["n_total"][:, None] * 0.002 ** 2 / (arrays["radii"][..., 0] * arrays["radii"][..., 1])
        assert np.allclose(arrays["density"], rho, rtol=2e-3)
    # A side file that disagrees with the stored arrays is named on load.
    membership_file = tmp_path / "asset" / manifest["thick_levels"][1]["per_hair"]["membership"]["file"]
    membership = np.load(membership_file)
    np.save(membership_file, np.roll(membership, 1))
    with pytest.raises(ValueError, match="membership of thick level 1"):
        lod.load(tmp_path / "asset")


def test_pack_unpack_gives_an_identical_asset(asset):
    from hairlod import lod

    data = lod.pack(asset)
    assert isinstance(data, bytes) and len(data) < asset.memory_bytes
    again = lod.unpack(data)
    _assert_same_asset(asset, again)
    kept = asset.with_levels([0, 2])
    _assert_same_asset(kept, lod.unpack(lod.pack(kept)))
    with pytest.raises(ValueError, match="not a packed hairlod LoD asset"):
        lod.unpack(data[: len(data) // 2], where="half")


def test_build_reports_progress_and_cancels_from_another_thread():
    import threading

    from hairlod import lod

    hair = hanging_hair(curves=6000, points=12)
    progress = lod.BuildProgress()
    lod.build_lod(hair, guides=16, levels=5, control_points=8, progress=progress)
    assert progress.done == progress.total == 4 + 3 + 4
    progress, outcome = lod.BuildProgress(), {}

    def build():
        try:
            outcome["asset"] = lod.build_lod(hair, guides=16, levels=5, control_points=8, progress=progress)
        except lod.BuildCancelled as error:
            outcome["cancelled"] = error

    worker = threading.Thread(target=build)
    worker.start()
    progress.cancel()  # the build stops at its next step, at the latest
    worker.join()
    assert "cancelled" in outcome and "asset" not in outcome and progress.cancelled


def test_keep_scene_levels_always_keeps_l0(asset):
    from hairlod import lod

    projection = perspective(math.radians(45), 4 / 3, 0.01, 1000)
    near = {"view": look_at((1.6, 0.3, 0.2), (0, 0, -0.3)), "projection": projection, "viewport": (1600, 1200)}
    selected = lod.scene_levels(asset, [near])
    assert min(selected) > 0  # this close, no cluster is drawn at L0
    kept, again = lod.keep_scene_levels(asset, [near])
    assert again == selected
    assert kept.level_ids == sorted({0} | {level for level in selected if level < len(asset.levels)})
    assert np.array_equal(kept.levels[0].n_total, asset.levels[0].n_total)
