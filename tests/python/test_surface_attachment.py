"""hairlod.surface_attachment: curves moved with the mesh they are attached to (the C++ behind it is
tested in tests/cpp/surface_attachment_test.cpp; here the Python surface and its errors)."""

import numpy as np
import pytest

from hairlod import surface_attachment


def quad_mesh():
    """Two triangles over the unit square in UV and in the xy plane, normals +z."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    corner_verts = np.array([0, 1, 2, 0, 2, 3], np.int32)
    triangles = np.array([[0, 1, 2], [3, 4, 5]], np.int32)
    corner_uvs = positions[corner_verts, :2]
    normals = np.tile([0.0, 0.0, 1.0], (6, 1)).astype(np.float32)
    return positions, corner_verts, triangles, corner_uvs, normals


def rotation(axis, angle):
    axis = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def test_a_turned_and_moved_mesh_turns_and_moves_its_curves():
    positions, corner_verts, triangles, corner_uvs, normals = quad_mesh()
    roots = np.array([[0.25, 0.1], [0.2, 0.7], [2.0, 2.0]], np.float32)  # the last lies outside the map
    follow = surface_attachment.SurfaceFollow(roots, corner_uvs, triangles, corner_verts, positions, normals, np.eye(4))
    assert follow.bound.tolist() == [True, True, False]
    turn, shift = rotation((1, 2, 3), 0.8), np.array([0.5, -1.0, 2.0])
    transforms = follow.transforms(positions @ turn.T + shift, normals @ turn.T, np.eye(4))
    assert transforms.shape == (3, 3, 4) and transforms.dtype == np.float32
    curves = np.random.default_rng(0).normal(size=(3, 5, 3)).astype(np.float32)
    moved = surface_attachment.apply(transforms, curves)
    np.testing.assert_allclose(moved[:2], curves[:2] @ turn.T + shift, atol=1e-5)
    np.testing.assert_array_equal(moved[2], curves[2])  # unbound: where it was


def test_transforms_written_into_an_array_kept_from_pose_to_pose_are_the_new_arrays():
    """The preview writes each pose's transforms into one of two arrays it keeps: every entry is written
    (unbound curves' identity too), so whatever the array held before does not show through."""
    positions, corner_verts, triangles, corner_uvs, normals = quad_mesh()
    roots = np.array([[0.25, 0.1], [2.0, 2.0], [0.2, 0.7]], np.float32)  # the middle one unbound
    follow = surface_attachment.SurfaceFollow(roots, corner_uvs, triangles, corner_verts, positions, normals, np.eye(4))
    laid_out = np.full((8, 3, 4), np.nan, np.float32)  # padded past the curves, as the preview lays them out
    for angle in (0.3, -1.1):
        turn = rotation((0, 1, 1), angle)
        expected = follow.transforms(positions @ turn.T, normals @ turn.T, np.eye(4))
        written = follow.transforms(positions @ turn.T, normals @ turn.T, np.eye(4), out=laid_out[:3])
        assert np.shares_memory(written, laid_out)
        np.testing.assert_array_equal(laid_out[:3], expected)
        np.testing.assert_array_equal(laid_out[1], np.eye(3, 4))
        assert np.isnan(laid_out[3:]).all()  # past the curves: untouched
    for bad in (np.zeros((3, 3, 4), np.float64), np.zeros((2, 3, 4), np.float32), np.zeros((3, 4, 3), np.float32),
                np.zeros((3, 3, 8), np.float32)[:, :, ::2]):
        with pytest.raises(ValueError, match=r"out must be a writeable, C-contiguous float32 array of shape \[3, 3, 4\]"):
            follow.transforms(positions, normals, np.eye(4), out=bad)


def test_a_changed_mesh_and_bad_shapes_are_clear_errors():
    positions, corner_verts, triangles, corner_uvs, normals = quad_mesh()
    follow = surface_attachment.SurfaceFollow(np.array([[0.5, 0.2]]), corner_uvs, triangles, corner_verts, positions,
                                              normals, np.eye(4))
    with pytest.raises(ValueError, match="3 vertices and 6 corner normals now, 4 and 6"):
        follow.transforms(positions[:3], normals, np.eye(4))
    with pytest.raises(ValueError, match=r"surface_to_curves must be a 4x4 matrix"):
        follow.transforms(positions, normals, np.eye(3))
    with pytest.raises(ValueError, match=r"root_uvs must have shape \[N, 2\]"):
        surface_attachment.SurfaceFollow(np.zeros((2, 3)), corner_uvs, triangles, corner_verts, positions, normals, np.eye(4))
    with pytest.raises(ValueError, match="names corner 9"):
        surface_attachment.SurfaceFollow(np.zeros((1, 2)), corner_uvs, np.array([[0, 1, 9]]), corner_verts, positions,
                                         normals, np.eye(4))
