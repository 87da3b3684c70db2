"""Camera matrices in Blender's convention (numpy rows are matrix rows, column vectors, OpenGL clip
space): what LoD selection and the benchmarks take as view and projection."""

import numpy as np

__all__ = ["look_at", "perspective"]


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    """World-to-camera matrix of a camera at `eye` looking at `target` (camera looks down -z)."""
    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    forward = target - eye
    forward /= np.linalg.norm(forward)
    side = np.cross(forward, up)
    if np.linalg.norm(side) < 1e-12:
        raise ValueError("look_at: the view direction is parallel to 'up'")
    side /= np.linalg.norm(side)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = side, np.cross(side, forward), -forward
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def perspective(fov_y, aspect, near, far):
    """OpenGL perspective projection; `fov_y` in radians."""
    if not (0 < fov_y < np.pi and aspect > 0 and 0 < near < far):
        raise ValueError(f"perspective: need 0 < fov_y < pi, aspect > 0 and 0 < near < far, "
                         f"got {fov_y}, {aspect}, {near}, {far}")
    f = 1.0 / np.tan(fov_y / 2.0)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]])
