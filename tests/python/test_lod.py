"""hairlod.lod: build, per-level invariants, skinning of rigid motions, selection."""

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
    assert all(2.0 < r < 8.0 for r in ratios)


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
