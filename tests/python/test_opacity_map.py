"""The geometry of the preview's deep opacity maps (hairlod/opacity_map.py); the maps drawn on the GPU
are checked against these formulas in tests/ui/test_opacity_map.py."""

import numpy as np
import pytest

from hairlod import opacity_map


def project(projection, points):
    points = np.asarray(points, np.float64)
    clip = np.concatenate([points, np.ones((len(points), 1))], axis=1) @ projection.view_projection.T
    return clip[:, :3] / clip[:, 3:]


def sphere_points(centre, radius, count=2000, seed=0):
    directions = np.random.default_rng(seed).normal(size=(count, 3))
    return np.asarray(centre) + radius * directions / np.linalg.norm(directions, axis=1, keepdims=True)


@pytest.mark.parametrize("towards", [(0.0, 0.0, 1.0), (0.3, -0.5, 0.81), (0.0, 1.0, 0.0), (-1.0, 0.0, -0.02)])
def test_a_sun_sees_the_whole_sphere_nearest_side_first(towards):
    towards = np.asarray(towards) / np.linalg.norm(towards)
    centre, radius = np.array([0.5, -2.0, 1.0]), 1.5
    projection = opacity_map.light_projection((*towards, 0.0), centre, radius, tile=256)
    assert not projection.perspective
    assert projection.pixel_size == pytest.approx(2.0 * radius / 256)
    ndc = project(projection, sphere_points(centre, radius))
    assert np.abs(ndc).max() <= 1.0 + 1e-9
    near, far = project(projection, [centre + radius * towards, centre - radius * towards])[:, 2]
    assert near == pytest.approx(-1.0) and far == pytest.approx(1.0)
    # Depth grows away from the sun, as the shader's light_depth (-dot(towards, p)) does.
    along = centre[None, :] - np.linspace(-1, 1, 5)[:, None] * radius * towards[None, :]
    assert np.all(np.diff(project(projection, along)[:, 2]) > 0.0)


def test_a_point_light_sees_the_sphere_within_its_view_and_none_from_inside():
    centre, radius = np.array([0.0, 0.0, 1.0]), 0.5
    position = np.array([3.0, 1.0, 2.0])
    projection = opacity_map.light_projection((*position, 1.0), centre, radius, tile=512)
    assert projection.perspective
    ndc = project(projection, sphere_points(centre, radius))
    assert np.abs(ndc).max() <= 1.0 + 1e-9
    assert np.abs(ndc[:, :2]).max() > 0.95  # the sphere fills the view
    distance = np.linalg.norm(centre - position)
    assert projection.pixel_at(distance) == pytest.approx(projection.pixel_size * distance)
    assert opacity_map.light_projection((*centre, 1.0), centre, radius) is None
    assert opacity_map.light_projection((0.0, 0.0, 1.2, 1.0), centre, radius) is None
    with pytest.raises(ValueError, match="radius must be positive"):
        opacity_map.light_projection((0.0, 0.0, 1.0, 0.0), centre, 0.0)


def test_optical_depth_is_piecewise_linear_through_the_layers():
    layers = np.array([0.5, 1.5, 2.0, 4.0])
    spacing = 0.1
    knots = np.concatenate([[0.0], np.asarray(opacity_map.LAYER_STEPS) * spacing])
    values = np.concatenate([[0.0], layers])
    # Above the first hair, on the boundaries, halfway between them and beyond the last one.
    below = np.concatenate([[-1.0], knots, 0.5 * (knots[:-1] + knots[1:]), [3.0 * knots[-1]]])
    expected = np.concatenate([[0.0], values, 0.5 * (values[:-1] + values[1:]), [layers[-1]]])
    np.testing.assert_allclose(opacity_map.optical_depth(layers, below, spacing), expected)
    # Per-texel layers broadcast against per-texel depths.
    many = np.stack([layers, 2.0 * layers])
    halfway = 0.5 * (knots[2] + knots[3])
    np.testing.assert_allclose(opacity_map.optical_depth(many, [halfway, halfway], spacing), [1.75, 3.5])
    assert opacity_map.layer_spacing(2.0) * opacity_map.LAYER_STEPS[-1] == pytest.approx(2.0)


def test_the_optical_depth_behind_runs_from_the_whole_hair_to_none():
    spacing = 0.5
    layers = np.array([1.0, 2.0, 3.5, 5.0])
    knots = np.asarray(opacity_map.LAYER_STEPS) * spacing
    # Above the first hair all of it lies behind; past the last layer none; between, what the layers
    # hold below the depth, never increasing.
    assert opacity_map.optical_depth_behind(layers, -1.0, spacing) == 5.0
    assert opacity_map.optical_depth_behind(layers, 0.0, spacing) == 5.0
    assert opacity_map.optical_depth_behind(layers, knots[-1] * 1.5, spacing) == 0.0
    np.testing.assert_allclose(opacity_map.optical_depth_behind(layers, knots, spacing), [4.0, 3.0, 1.5, 0.0])
    depths = np.linspace(0.0, knots[-1], 50)
    assert np.all(np.diff(opacity_map.optical_depth_behind(layers, depths, spacing)) <= 0.0)


def test_a_thick_hair_adds_the_optical_depth_of_its_strands():
    """Across its silhouette a thick hair holds 2 r N, its strands' projected width (Beer-Lambert sums
    coverage), whatever its width; a strand's line adds 2 r over the pixel's width, capped."""
    radius, strands = 0.001, 40
    for half_width in (0.02, 0.05, 0.2):
        across = np.linspace(-1.0, 1.0, 200001)
        values = opacity_map.thick_hair_coverage(radius, strands, half_width, across)
        x = across * half_width
        width = float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(x)))  # trapezoids
        assert width == pytest.approx(2.0 * radius * strands, rel=1e-4)
    assert opacity_map.strand_coverage(0.001, 0.004) == pytest.approx(0.5)
    assert opacity_map.strand_coverage(0.1, 0.001) == opacity_map.MAX_PIXEL_DEPTH


def test_the_maps_draw_the_finest_level_within_the_budget():
    assert opacity_map.shadow_level([1000, 5000, 40000, 300000], budget=50000) == 2
    assert opacity_map.shadow_level([1000, 5000, 40000, 30000], budget=50000) == 3
    assert opacity_map.shadow_level([100000, 300000], budget=50000) == 0
    assert opacity_map.shadow_level([10, 20]) == 1
