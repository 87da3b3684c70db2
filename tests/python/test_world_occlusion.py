"""The hair's occlusion of the world on a grid (hairlod.world_occlusion): its optical depths against
the analytic chords through simple hair, the sweep against a brute-force march, a hollow shell and
hanging tips as the ellipsoid could not hold them, moved hair, and bad input."""

import numpy as np
import pytest

from hairlod import self_shadow, world_occlusion
from hairlod.self_shadow import WORLD_DIRECTIONS

RADIUS = 0.001


def lattice_slab(spacing=0.01, thickness=0.2):
    """Straight strands along x from 0 to 1, on a square lattice over y in [0, 1], z in [0, thickness]:
    a slab of extinction 2 r / spacing^2 across the strands (2 r |sin theta| / spacing^2 at angle theta
    to them)."""
    ys, zs = np.meshgrid(np.arange(0.0, 1.0 + 1e-9, spacing), np.arange(0.0, thickness + 1e-9, spacing), indexing="ij")
    count = ys.size
    x = np.linspace(0.0, 1.0, 11)
    points = np.empty((count, len(x), 3))
    points[:, :, 0] = x
    points[:, :, 1] = ys.reshape(-1, 1)
    points[:, :, 2] = zs.reshape(-1, 1)
    offsets = np.arange(0, count * len(x) + 1, len(x))
    return points.reshape(-1, 3), offsets, np.full(count * len(x), RADIUS), 2.0 * RADIUS / spacing ** 2


def fibonacci_directions(count):
    """Unit vectors spread evenly over the sphere (a Fibonacci lattice)."""
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    phi = np.pi * (1.0 + 5.0 ** 0.5) * k
    ring = np.sqrt(1.0 - z * z)
    return np.stack([ring * np.cos(phi), ring * np.sin(phi), z], axis=1)


def radial_shell(count=4000, inner=0.5, outer=1.0, strand_points=11):
    """Straight radial strands from radius `inner` to `outer`: the extinction at radius r between them
    is count 2 r_f |sin theta| / (4 pi r^2) towards a direction at angle theta to the radius; returns the
    strands and that extinction as a function of points [N, 3] and a unit direction."""
    directions = fibonacci_directions(count)
    radii = np.linspace(inner, outer, strand_points)
    points = (directions[:, None, :] * radii[None, :, None]).reshape(-1, 3)

    def density(p, direction):
        r = np.linalg.norm(p, axis=-1)
        along = (p @ direction) / np.maximum(r, 1e-12)
        sin_theta = np.sqrt(np.clip(1.0 - along * along, 0.0, 1.0))
        return np.where((r > inner) & (r < outer),
                        count * 2.0 * RADIUS * sin_theta / (4.0 * np.pi * np.maximum(r, 1e-9) ** 2), 0.0)

    return points, np.arange(0, len(points) + 1, len(radii)), np.full(len(points), RADIUS), density


def marched_depth(density, point, direction, reach=3.0, steps=30000):
    """The optical depth from `point` along `direction` by the midpoint rule over `reach`."""
    s = (np.arange(steps) + 0.5) * (reach / steps)
    return float(np.sum(density(point + s[:, None] * direction, direction)) * reach / steps)


def test_depths_in_a_slab_are_its_chords():
    points, offsets, radius, sigma = lattice_slab()
    occlusion = world_occlusion.world_occlusion(points, offsets, radius)
    probe = np.array([[0.5, 0.5, 0.1], [0.3, 0.6, 0.05], [0.7, 0.4, 0.15]])
    depths = world_occlusion.optical_depths(occlusion, probe)
    # Towards +-z the chord to the slab's faces, across the strands (+-y) to its sides.
    expected_z = sigma * np.stack([0.2 - probe[:, 2], probe[:, 2]], axis=1)
    # The splat spreads each strand over the voxels beside it: the faces blur by about a voxel (0.02).
    np.testing.assert_allclose(depths[:, [2, 5]], expected_z, rtol=0.0, atol=sigma * 0.025)
    np.testing.assert_allclose(depths[:, [1, 4]], sigma * np.stack([1.0 - probe[:, 1], probe[:, 1]], axis=1),
                               rtol=0.0, atol=sigma * 0.03)
    # Along the strands (+-x) the light passes them: a fibre seen end on shows no width.
    assert np.all(depths[:, [0, 3]] < 1e-6 * sigma)
    # A diagonal leaves through the nearer face in z, sqrt(3) times that face's distance, at sin^2 = 2 / 3
    # to the strands.
    up = [k for k in range(6, 14) if WORLD_DIRECTIONS[k, 2] > 0]
    np.testing.assert_allclose(depths[0, up], sigma * np.sqrt(2.0 / 3.0) * np.sqrt(3.0) * 0.1, rtol=0.1)


def test_depths_in_a_hollow_shell_match_a_march_through_its_density():
    points, offsets, radius, density = radial_shell()
    occlusion = world_occlusion.world_occlusion(points, offsets, radius, max_samples=10 ** 6)
    probe = np.array([[0.0, 0.0, 0.0], [0.75, 0.0, 0.0], [0.0, -0.3, 0.2], [0.45, 0.45, 0.3]])
    depths = world_occlusion.optical_depths(occlusion, probe)
    expected = np.array([[marched_depth(density, p, d) for d in WORLD_DIRECTIONS] for p in probe])
    # The grid (48 voxels across) blurs the shell's faces and the hollow's edge by about a voxel, and
    # mixes the tangents of the strands a voxel apart (0.08 rad at the inner radius) where a ray runs
    # along them.
    np.testing.assert_allclose(depths, expected, rtol=0.1, atol=0.04 * expected.max())
    # From the empty centre every direction runs along the radial strands, which let it through; the
    # bounding ellipsoid, a medium crossed at right angles, finds a whole radius of it there.
    assert np.all(depths[0] < 0.05 * expected.max())
    volume = self_shadow.hair_volume(points, offsets, radius)
    assert volume.extinction * 1.0 > 0.5 * expected.max()


def test_a_tip_below_the_hair_is_shaded_from_above_only():
    points, offsets, radius, sigma = lattice_slab()
    # One strand hangs from the slab's middle down to z = -0.5: its tip sees the slab above it only.
    hanging = np.array([[0.5, 0.5, 0.1], [0.5, 0.5, -0.2], [0.5, 0.5, -0.5]])
    points = np.vstack([points, hanging])
    offsets = np.append(offsets, offsets[-1] + 3)
    radius = np.append(radius, np.full(3, RADIUS))
    occlusion = world_occlusion.world_occlusion(points, offsets, radius)
    # Beside the hanging strand (3 voxels off its line, out of its own splat).
    tip = world_occlusion.optical_depths(occlusion, [[0.56, 0.5, -0.45]])[0]
    assert tip[2] == pytest.approx(sigma * 0.2, rel=0.1)  # up through the whole slab
    assert np.all(tip[[0, 1, 3, 4, 5]] < 0.01 * sigma)  # sideways and down: open


def brute_force_depth(density, step, voxel):
    """The sweep's trapezoids, one voxel at a time: from each voxel along `step` until past the grid."""
    tau = np.zeros_like(density)
    shape = np.array(density.shape)
    length = voxel * np.linalg.norm(step)
    for index in np.ndindex(*density.shape):
        here = np.array(index)
        total = 0.0
        while np.all(here >= 0) and np.all(here < shape):
            ahead = here + step
            inside = np.all(ahead >= 0) and np.all(ahead < shape)
            total += 0.5 * length * (density[tuple(here)] + (density[tuple(ahead)] if inside else 0.0))
            here = ahead
        tau[index] = total
    return tau


@pytest.mark.parametrize("direction", range(14))
def test_sweep_matches_a_brute_force_march(direction):
    rng = np.random.default_rng(direction)
    density = rng.uniform(size=(5, 6, 4))
    step = world_occlusion._GRID_STEPS[direction]
    np.testing.assert_allclose(world_occlusion._sweep(density, step, 0.3), brute_force_depth(density, step, 0.3),
                               rtol=1e-12)


def test_fewer_strands_stand_for_all():
    # Strands dense against the voxels (the fifth of them 0.03 apart at the inner radius, voxels 0.04),
    # in no spatial order (as a hair's roots are; the Fibonacci lattice's every fifth is a spiral).
    # Segments shorter than half a voxel: one sample each, and max_samples a fifth of the points keeps
    # every fifth strand.
    points, _, radius, _ = radial_shell(count=20000, strand_points=31)
    points = points.reshape(20000, -1, 3)[np.random.default_rng(7).permutation(20000)].reshape(-1, 3)
    offsets = np.arange(0, len(points) + 1, 31)
    full = world_occlusion.world_occlusion(points, offsets, radius, max_samples=10 ** 7)
    every_fifth = world_occlusion.world_occlusion(points, offsets, radius, max_samples=len(points) // 5)
    probe = np.array([[0.0, 0.0, 0.0], [0.75, 0.0, 0.0], [0.0, -0.7, 0.3], [0.2, 0.1, 0.9]])
    # What the shading reads: the light through the 14 directions, at a density that halves it.
    fewer = world_occlusion.world_transmittance(probe, every_fifth, 0.2)
    np.testing.assert_allclose(fewer, world_occlusion.world_transmittance(probe, full, 0.2), rtol=0.05)
    assert fewer.min() < 0.8


def test_transmittance_averages_the_directions_per_channel():
    points, offsets, radius, _ = radial_shell()
    occlusion = world_occlusion.world_occlusion(points, offsets, radius)
    probe = [[0.9, 0.0, 0.0]]
    tau = world_occlusion.optical_depths(occlusion, probe)[0]
    assert world_occlusion.world_transmittance(probe, occlusion, 2.0)[0] == pytest.approx(np.mean(np.exp(-2.0 * tau)))
    keep = np.array([1.0, 0.5, 0.25])
    np.testing.assert_allclose(world_occlusion.world_transmittance(probe, occlusion, 2.0, keep=keep)[0],
                               np.mean(np.exp(-2.0 * tau[:, None] * keep), axis=0))
    assert world_occlusion.world_transmittance(probe, occlusion, 0.0)[0] == 1.0
    with pytest.raises(ValueError, match="keep must have shape"):
        world_occlusion.world_transmittance(probe, occlusion, 1.0, keep=np.ones((13, 3)))
    with pytest.raises(ValueError, match="strength"):
        world_occlusion.world_transmittance(probe, occlusion, float("nan"))


def test_moved_hair_carries_its_grid():
    points, offsets, radius, _ = radial_shell()
    rest = world_occlusion.world_occlusion(points, offsets, radius)
    box = (points.min(0), points.max(0))
    shift = np.array([0.3, -2.0, 5.0])
    moved = world_occlusion.moved_occlusion(rest, box, (box[0] + shift, box[1] + shift))
    probe = np.array([[0.9, 0.0, 0.0], [0.1, 0.2, -0.85]])
    np.testing.assert_allclose(world_occlusion.optical_depths(moved, probe + shift),
                               world_occlusion.optical_depths(rest, probe), rtol=1e-12)
    # Stretched twice as wide everywhere: the same strands over 8 times the volume, paths twice as long.
    grown = world_occlusion.moved_occlusion(rest, box, (2.0 * box[0], 2.0 * box[1]))
    np.testing.assert_allclose(world_occlusion.optical_depths(grown, 2.0 * probe),
                               world_occlusion.optical_depths(rest, probe) / 4.0, rtol=1e-12)


def test_hair_in_one_place_occludes_nothing():
    occlusion = world_occlusion.world_occlusion(np.zeros((4, 3)), [0, 2, 4], np.full(4, RADIUS))
    assert np.all(world_occlusion.optical_depths(occlusion, [[0.0, 0.0, 0.0], [5.0, 0.0, 0.0]]) == 0.0)


@pytest.mark.parametrize("points, offsets, radius, message", [
    (np.zeros((1, 3)), [0, 1], np.ones(1), "points must have shape"),
    (np.zeros((4, 2)), [0, 4], np.ones(4), "points must have shape"),
    (np.zeros((4, 3)), [0, 4], np.ones(3), "radius must have shape"),
    (np.zeros((4, 3)), [0, 3], np.ones(4), "offsets must run from 0 to 4"),
    (np.zeros((4, 3)), [0, 2, 2, 4], np.ones(4), "offsets must rise"),
    (np.full((4, 3), np.nan), [0, 4], np.ones(4), "finite"),
])
def test_bad_strands_are_named(points, offsets, radius, message):
    with pytest.raises(ValueError, match=message):
        world_occlusion.world_occlusion(points, offsets, radius)


def test_strands_occlusion_equals_the_occlusion_of_the_arrays():
    # The preview's path (the core's float32 arrays and bounding box) against the arrays', thinned alike.
    import hairlod

    rng = np.random.default_rng(4)
    counts = rng.integers(2, 9, 3000)
    points = rng.normal(size=(int(counts.sum()), 3)).astype(np.float32) * [1.0, 2.0, 0.5]
    radius = rng.uniform(0.001, 0.01, len(points)).astype(np.float32)
    strands = hairlod.Strands.from_counts(points, counts, radius)
    fast = world_occlusion.strands_occlusion(strands, max_samples=5000)
    reference = world_occlusion.world_occlusion(points, strands.offsets, radius, max_samples=5000)
    np.testing.assert_allclose(fast.lower, reference.lower, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(fast.extent, reference.extent, rtol=1e-6)
    np.testing.assert_allclose(fast.optical_depths, reference.optical_depths, rtol=1e-4, atol=1e-6)
    assert reference.optical_depths.max() > 0.0


def test_the_cores_splat_names_bad_input():
    # The core's function behind the grid checks what it splats itself (world_occlusion checks first).
    from hairlod import _core

    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [np.nan, 0.0, 0.0]], np.float32)
    args = ([0, 2, 3], np.full(3, RADIUS, np.float32), np.zeros(3), np.ones(3), 8, 1000, 0.5)
    with pytest.raises(ValueError, match="points and radii must be finite"):
        _core.strand_density(points, *args)
    with pytest.raises(ValueError, match="offsets must run from 0 to 2"):
        _core.strand_density(points[:2], *args)
    fields, voxel, step = _core.strand_density(points[:2], [0, 2], np.full(2, RADIUS, np.float32), np.zeros(3),
                                               np.ones(3), 8, 1000, 0.5)
    # One segment of length 1 and radius RADIUS: its projected area 2 r l, all of it on the grid.
    assert fields.shape[0] == 7 and step == 1
    assert fields[0].sum() * voxel ** 3 == pytest.approx(2.0 * RADIUS, rel=1e-6)
