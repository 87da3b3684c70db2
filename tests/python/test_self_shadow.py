"""The preview's self-shadowing reference (hairlod.self_shadow): 1 on the lit side, falling into the
hair, finite on hard cases."""

import numpy as np
import pytest

from hairlod import self_shadow

SUN_FROM_X = np.array([1.0, 0.0, 0.0, 0.0])  # a sun in +x


def ball(count=400, seed=3):
    """Straight strands filling the unit ball, 4 points each: a hair volume close to the unit sphere."""
    rng = np.random.default_rng(seed)
    roots = rng.normal(size=(count, 3))
    roots *= (rng.uniform(size=(count, 1)) ** (1 / 3)) / np.linalg.norm(roots, axis=1, keepdims=True)
    roots[:6] = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]  # extent exactly 1
    points = roots[:, None, :] + np.linspace(0.0, 0.02, 4)[None, :, None] * np.array([0.0, 0.0, -1.0])
    points = np.clip(points, -1.0, 1.0).reshape(-1, 3)
    return points, np.arange(0, 4 * count + 1, 4), np.full(len(points), 0.001)


def test_volume_bounds_the_strands_and_measures_their_extinction():
    points, offsets, radius = ball()
    volume = self_shadow.hair_volume(points, offsets, radius)
    np.testing.assert_allclose(volume.semi_axes, 0.5 * (points.max(0) - points.min(0)))
    # 2 r L / V with each strand 0.02 long (clipping shortens a few at the boundary).
    expected = 2 * 0.001 * 400 * 0.02 / (4 / 3 * np.pi * np.prod(volume.semi_axes))
    assert volume.extinction == pytest.approx(expected, rel=0.02)


def test_one_on_the_lit_side_and_falling_into_the_hair():
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.ones(3), extinction=2.0)
    x = np.linspace(1.0, -1.0, 9)
    points = np.stack([x, np.zeros(9), np.zeros(9)], axis=1)
    t = self_shadow.transmittance(points, SUN_FROM_X, volume, strength=0.5)
    assert t[0] == pytest.approx(1.0)
    assert (np.diff(t) < 0).all()
    # Depth 1 - x along the axis, sigma = 0.5 x 2.
    np.testing.assert_allclose(t, np.exp(-(1.0 - x)))
    # Outside, on the far side: the whole chord (2) shadows it; beside the volume, nothing does.
    far_and_beside = self_shadow.transmittance([[-3.0, 0, 0], [0, 2.0, 0]], SUN_FROM_X, volume, 0.5)
    np.testing.assert_allclose(far_and_beside, [np.exp(-2.0), 1.0])


def test_point_light_path_ends_at_the_light():
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.array([2.0, 1.0, 1.0]), extinction=1.0)
    light_inside = np.array([1.0, 0.0, 0.0, 1.0])
    t = self_shadow.transmittance([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]], light_inside, volume, 1.0)
    np.testing.assert_allclose(t, [np.exp(-2.0), 1.0])  # 2 units of hair between; the light itself


def test_zero_strength_or_density_disables_it():
    points = np.random.default_rng(0).uniform(-1, 1, (50, 3))
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.ones(3), extinction=3.0)
    np.testing.assert_array_equal(self_shadow.transmittance(points, SUN_FROM_X, volume, 0.0), 1.0)
    empty = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.ones(3), extinction=0.0)
    np.testing.assert_array_equal(self_shadow.transmittance(points, SUN_FROM_X, empty, 1.0), 1.0)


def test_hard_cases_are_finite_and_bounded():
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.array([1.0, 1e-3, 1.0]), extinction=50.0)
    rng = np.random.default_rng(1)
    points = np.concatenate([rng.uniform(-1, 1, (200, 3)), [[0, 0, 0], [1, 0, 0], [1e6, -1e6, 0]]])
    lights = np.concatenate([
        np.tile([0.0, 0.0, 0.0, 0.0], (67, 1)),                     # a zero sun direction
        np.concatenate([points[67:134], np.ones((67, 1))], axis=1),  # a point light at the point itself
        np.tile([0.0, 1.0, 0.0, 0.0], (66, 1)),                      # across the flat axis
        [[1e-20, 0.0, 0.0, 0.0], [0.0, 0.0, 1e20, 1.0], [1.0, 0.0, 0.0, 0.0]]])
    t = self_shadow.transmittance(points, lights, volume, 1.0)
    assert np.isfinite(t).all() and (t > 0.0).all() and (t <= 1.0).all()
    np.testing.assert_array_equal(t[:134], 1.0)  # no path to the light: nothing in between


def test_light_along_the_strands_shadows_by_depth_alone():
    """The estimate does not depend on the fibre tangent: a light parallel to the strands shadows
    the same points as any other light at the same depth."""
    points, offsets, radius = ball()
    volume = self_shadow.hair_volume(points, offsets, radius)
    along = np.array([0.0, 0.0, 1.0, 0.0])  # the strands run along -z
    t = self_shadow.transmittance(points, along, volume, 1.0)
    assert np.isfinite(t).all() and (t <= 1.0).all()
    top, bottom = points[:, 2] > 0.5, points[:, 2] < -0.5
    assert t[top].mean() > t[bottom].mean()


def test_flat_or_degenerate_hair_has_a_finite_volume():
    flat = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    volume = self_shadow.hair_volume(flat, [0, 2, 4], np.full(4, 0.01))
    assert (volume.semi_axes > 0).all() and np.isfinite(volume.extinction)
    point = self_shadow.hair_volume(np.zeros((2, 3)), [0, 2], np.full(2, 0.01))
    assert point.extinction == 0.0


@pytest.mark.parametrize("points, offsets, radius, message", [
    (np.zeros((1, 3)), [0, 1], np.ones(1), "points must have shape"),
    (np.zeros((4, 3)), [0, 4], np.ones(3), "radius must have shape"),
    (np.zeros((4, 3)), [0, 3], np.ones(4), "offsets must run"),
    (np.full((4, 3), np.nan), [0, 4], np.ones(4), "must be finite"),
])
def test_bad_strands_raise_clear_errors(points, offsets, radius, message):
    with pytest.raises(ValueError, match=message):
        self_shadow.hair_volume(points, offsets, radius)


def test_bad_strength_raises():
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.ones(3), extinction=1.0)
    with pytest.raises(ValueError, match="strength"):
        self_shadow.transmittance([[0, 0, 0]], SUN_FROM_X, volume, -1.0)


def test_strands_volume_equals_the_volume_of_the_arrays():
    # The preview's fast path (the core's bounding box and curve lengths) against the numpy reference.
    import hairlod

    rng = np.random.default_rng(4)
    counts = rng.integers(2, 9, 50)
    points = rng.normal(size=(int(counts.sum()), 3)).astype(np.float32) * [1.0, 2.0, 0.5]
    radius = rng.uniform(0.001, 0.01, len(points)).astype(np.float32)
    strands = hairlod.Strands.from_counts(points, counts, radius)
    fast, reference = self_shadow.strands_volume(strands), self_shadow.hair_volume(points, strands.offsets, radius)
    np.testing.assert_allclose(fast.centre, reference.centre, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(fast.semi_axes, reference.semi_axes, rtol=1e-6)
    assert fast.extinction == pytest.approx(reference.extinction, rel=1e-5)


def test_world_transmittance_averages_the_suns_of_its_directions():
    # Outside the volume, every direction that misses it passes all the light; at the centre of a
    # sphere every direction crosses one radius: exp(-sigma r).
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.full(3, 2.0), extinction=0.5)
    assert self_shadow.world_transmittance([[0.0, 0.0, 0.0]], volume, 1.0)[0] == pytest.approx(np.exp(-1.0), rel=1e-12)
    far_away = self_shadow.world_transmittance([[100.0, 0.0, 0.0]], volume, 1.0)[0]
    assert 1.0 > far_away > 13.0 / 14.0  # only the direction back through the sphere is shadowed
    assert self_shadow.world_transmittance([[0.5, 0.2, 0.1]], volume, 0.0)[0] == 1.0
    # Per channel, each direction's T raised to keep before the average: at the centre of the sphere every
    # direction is the same, exp(-keep); off centre the mean of T^keep is below (mean T)^keep (Jensen),
    # and keep = 1 gives the plain average.
    keep = np.array([0.3, 0.6, 1.0])
    np.testing.assert_allclose(self_shadow.world_transmittance([[0.0, 0.0, 0.0]], volume, 1.0, keep=keep)[0],
                               np.exp(-keep), rtol=1e-12)
    off_centre = [[1.2, 0.4, -0.3]]
    per_channel = self_shadow.world_transmittance(off_centre, volume, 1.0, keep=keep)[0]
    plain = self_shadow.world_transmittance(off_centre, volume, 1.0)[0]
    assert np.all(per_channel[:2] < plain ** keep[:2]) and per_channel[2] == pytest.approx(plain, rel=1e-12)
    assert len(self_shadow.WORLD_DIRECTIONS) == 14
    np.testing.assert_allclose(np.linalg.norm(self_shadow.WORLD_DIRECTIONS, axis=1), 1.0)


def test_world_transmittance_takes_a_keep_per_direction():
    # keep per direction and channel [14, 3]: each direction's T raised to its own row. The same row for
    # every direction is the per-channel keep; at the centre of a sphere (every T = exp(-1)) the result
    # is the mean of exp(-keep) over the rows; a direction whose keep is 0 passes all its light.
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.full(3, 2.0), extinction=0.5)
    off_centre = [[1.2, 0.4, -0.3], [-0.5, 0.1, 0.9]]
    keep = np.array([0.3, 0.6, 1.0])
    np.testing.assert_allclose(self_shadow.world_transmittance(off_centre, volume, 1.0, keep=np.tile(keep, (14, 1))),
                               self_shadow.world_transmittance(off_centre, volume, 1.0, keep=keep), rtol=1e-12)
    rows = np.linspace(0.0, 1.0, 14)[:, None] * np.array([1.0, 0.5, 0.25])
    np.testing.assert_allclose(self_shadow.world_transmittance([[0.0, 0.0, 0.0]], volume, 1.0, keep=rows)[0],
                               np.exp(-rows).mean(axis=0), rtol=1e-12)
    # Brute force off centre: the suns of the directions one by one.
    suns = [self_shadow.transmittance(off_centre, np.append(d, 0.0), volume, 1.0) for d in self_shadow.WORLD_DIRECTIONS]
    expected = np.mean([t[:, None] ** row[None, :] for t, row in zip(suns, rows)], axis=0)
    np.testing.assert_allclose(self_shadow.world_transmittance(off_centre, volume, 1.0, keep=rows), expected, rtol=1e-12)
    with pytest.raises(ValueError, match="keep must have shape"):
        self_shadow.world_transmittance(off_centre, volume, 1.0, keep=np.ones((13, 3)))



def test_scattered_light_keeps_a_uniform_world_inside_hair_that_absorbs_nothing():
    """The white furnace: a uniform world around hair whose strands absorb nothing (rho = 1) lights every
    point inside it fully, however deep (the direct light T plus what the hair around scatters on)."""
    from hairlod import preview_luts

    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.array([1.0, 0.8, 0.6]), extinction=4.0)
    points = np.random.default_rng(5).uniform(-1.0, 1.0, (300, 3)) * volume.semi_axes
    keep = np.full(3, 0.4)
    transmittance = self_shadow.world_transmittance(points, volume, 1.0, keep=keep)
    assert transmittance.min() < 0.3  # deep points, where the direct light alone is far from the furnace
    lossless = preview_luts.scattering_albedo(preview_luts.shader_tables({"sigma_a": (0.0, 0.0, 0.0)}))
    np.testing.assert_allclose(transmittance * (1.0 + self_shadow.scattered_share(transmittance, lossless)), 1.0,
                               atol=1e-5)
    # Absorbing hair: more than the direct light, less than the furnace, more the more the strands scatter.
    brown = preview_luts.scattering_albedo(preview_luts.shader_tables({"sigma_a": (0.2, 0.4, 0.8)}))
    lit = transmittance * (1.0 + self_shadow.scattered_share(transmittance, brown))
    assert (lit >= transmittance - 1e-12).all() and (lit < 1.0).all()
    assert (lit[:, 0] >= lit[:, 2]).all()


def test_scattered_light_needs_hair_in_the_way_and_strands_that_scatter():
    transmittance = np.array([[1.0, 1.0, 1.0], [0.5, 0.5, 0.5], [0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(self_shadow.scattered_share(transmittance[0], [0.3, 0.6, 1.0]), 0.0)
    np.testing.assert_array_equal(self_shadow.scattered_share(transmittance, np.zeros(3)), 0.0)
    # T = 1/2, rho = 1/2: the light arriving is T / (1 - rho (1 - T)) = 2/3, one third more than T.
    assert self_shadow.scattered_share(0.5, 0.5) == pytest.approx(1.0 / 3.0)
    # Fully blocked and lossless (a point no light reaches in a furnace): finite, capped.
    assert np.isfinite(self_shadow.scattered_share(0.0, 1.0))
    # Out of range inputs are clamped to [0, 1].
    assert self_shadow.scattered_share(1.5, 0.5) == 0.0 and self_shadow.scattered_share(0.5, 2.0) == pytest.approx(1.0)


def test_world_transmittance_by_side_splits_the_directions_by_the_camera():
    """The world's light split by side (hair_world_transmittance in self_shadow.glsl): the mean over all
    directions is the count-weighted mean of the two sides; the camera's side holds the directions
    facing it, a direction across the view counts half to each side; no hair passes everything; with
    the hair behind the point (seen from the camera), the far side is the darker one."""
    volume = self_shadow.HairVolume(centre=np.zeros(3), semi_axes=np.array([1.0, 1.0, 1.0]), extinction=1.5)
    # A point on the sphere's camera-facing side, the camera towards +x.
    point = np.array([[0.9, 0.0, 0.0]])
    tau = self_shadow.world_depths(point, volume, 1.0)
    np.testing.assert_allclose(np.exp(-tau).mean(axis=1), self_shadow.world_transmittance(point, volume, 1.0), rtol=1e-12)
    facing = self_shadow.WORLD_DIRECTIONS @ np.array([1.0, 0.0, 0.0])
    keep = np.array([0.3, 0.5, 0.8])
    everything, near, far = self_shadow.world_transmittance_by_side(tau, keep, facing[None, :])
    np.testing.assert_allclose(everything, self_shadow.world_transmittance(point, volume, 1.0, keep=keep), rtol=1e-12)
    near_count = np.sum(np.where(facing > 1e-4, 1.0, np.where(facing < -1e-4, 0.0, 0.5)))
    assert near_count == 7.0  # +x, four diagonals, and +-y, +-z across the view counting half
    np.testing.assert_allclose((near_count * near + (14.0 - near_count) * far) / 14.0, everything, rtol=1e-12)
    assert np.all(far < near) and np.all(near > everything) and np.all(everything > far)
    # By hand, in red: the near side's weighted mean of each direction's own T^keep.
    weight = np.where(facing > 1e-4, 1.0, np.where(facing < -1e-4, 0.0, 0.5))
    assert near[0, 0] == pytest.approx(np.sum(weight * np.exp(-keep[0] * tau[0])) / weight.sum(), rel=1e-12)
    clear = self_shadow.world_transmittance_by_side(np.zeros((1, 14)), keep, facing[None, :])
    for part in clear:
        np.testing.assert_allclose(part, 1.0)
    # Every direction across the view: both sides hold them all, each half.
    _, near_across, far_across = self_shadow.world_transmittance_by_side(tau, keep, np.zeros((1, 14)))
    np.testing.assert_allclose(near_across, everything, rtol=1e-12)
    np.testing.assert_allclose(far_across, everything, rtol=1e-12)
