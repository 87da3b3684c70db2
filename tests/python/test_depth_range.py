"""The preview's projection fitted to the hair's depth range (hairlod/depth_range.py): points keep their
pixel, the viewport's depth comes back from the fitted one, and strands a tenth of a millimetre apart
at 40 m get different depths in a 24-bit depth buffer, where Blender's default projection merges them."""

import numpy as np
import pytest

from hairlod import depth_range


def perspective(fov_y, aspect, near, far):
    f = 1.0 / np.tan(0.5 * fov_y)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)], [0, 0, -1, 0]])


def orthographic(half_width, half_height, near, far):
    return np.array([[1 / half_width, 0, 0, 0], [0, 1 / half_height, 0, 0],
                     [0, 0, -2 / (far - near), -(far + near) / (far - near)], [0, 0, 0, 1]])


def window_depth(matrix, points):
    clip = np.c_[points, np.ones(len(points))] @ np.asarray(matrix).T
    return clip, 0.5 * clip[:, 2] / clip[:, 3] + 0.5


def quantised(depth):
    """A 24-bit unsigned normalised depth buffer's value."""
    return np.round(np.asarray(depth) * (2 ** 24 - 1)).astype(np.int64)


@pytest.mark.parametrize("projection", [perspective(0.7, 1.6, 0.01, 1000.0), orthographic(3.0, 2.0, -500.0, 500.0)])
def test_points_keep_their_pixel_and_their_viewport_depth(projection):
    view = np.eye(4)
    centre, radius = np.array([0.2, -0.1, -40.0]), 1.0
    rng = np.random.default_rng(3)
    points = centre + rng.normal(size=(500, 3)) * 0.4
    fitted = depth_range.fitted_projection(projection, view, centre, radius)
    clip, depth = window_depth(projection, points)
    fitted_clip, fitted_depth = window_depth(fitted.projection, points)
    np.testing.assert_array_equal(fitted_clip[:, [0, 1, 3]], clip[:, [0, 1, 3]])
    assert np.all((fitted_depth > 0.0) & (fitted_depth < 1.0))
    np.testing.assert_allclose(depth_range.viewport_depth(fitted_depth, fitted), depth, rtol=0, atol=1e-9)
    # The hair's depths spread over most of the fitted range, not a sliver of the viewport's.
    assert np.ptp(fitted_depth) > 0.2 and np.ptp(fitted_depth) > 100 * np.ptp(depth)


def test_strands_apart_by_a_tenth_of_a_millimetre_at_40_m_are_told_apart():
    projection, view = perspective(0.7, 1.6, 0.01, 1000.0), np.eye(4)
    centre = np.array([0.0, 0.0, -40.0])
    front, behind = centre + [0.0, 0.0, 1e-4], centre
    fitted = depth_range.fitted_projection(projection, view, centre, 0.15)
    viewport = quantised(window_depth(projection, np.array([front, behind]))[1])
    ours = quantised(window_depth(fitted.projection, np.array([front, behind]))[1])
    assert viewport[0] == viewport[1]  # Blender's default clip range: one depth for both
    assert ours[0] < ours[1]           # fitted: the nearer strand wins the depth test


def test_viewport_planes_still_clip():
    """The fitted planes never reach past the viewport's: a camera inside the hair keeps its near
    plane, hair beyond the far plane stays clipped, and hair behind the camera leaves the projection as
    it was."""
    projection, view = perspective(0.7, 1.6, 0.1, 50.0), np.eye(4)
    inside = depth_range.fitted_projection(projection, view, np.array([0.0, 0.0, -0.5]), 2.0)
    near, far = depth_range._clip_range(inside.planes[0], inside.planes[1], True)
    assert near == pytest.approx(0.1) and far == pytest.approx(0.5 + 1.5 * 2.0)
    beyond = depth_range.fitted_projection(projection, view, np.array([0.0, 0.0, -49.0]), 2.0)
    assert depth_range._clip_range(beyond.planes[0], beyond.planes[1], True)[1] == pytest.approx(50.0)
    behind = depth_range.fitted_projection(projection, view, np.array([0.0, 0.0, 10.0]), 2.0)
    np.testing.assert_array_equal(behind.projection, projection)
