"""A projection whose depth range holds only the hair: the LoD preview draws its hair with it into a
depth buffer of its own (blender/preview/hair_layer.py), so that the depth test orders strands.

A viewport's projection spans its Clip Start to Clip End (Blender's default 0.01 m to 1000 m). Its
depth buffer then tells apart depths about z^2 / (Clip Start 2^24) apart at distance z: 0.6 mm at
10 m, 10 mm at 40 m, many strand widths. Strands nearer each other than that win the depth test at
random, and the preview showed deeper, shadowed strands at a distance: the generated 20k hair's far
view read 0.84 / 0.86 / 0.73 of its path-traced radiance (R, G, B), and 1.01 / 1.08 / 1.01 with Clip
Start 1 m (scripts/bench_preview_fidelity.py). Moving the near and far planes to the hair's bounding
sphere leaves rows 0, 1 and 3 of the matrix, so every point keeps its pixel and w, and gives the
depth buffer's steps to the hair alone. The preview writes the viewport's own depth of each hair
pixel back (viewport_depth), so that the scene's objects hide the hair as before.

Depth planes (A, B) are a projection's row 2: z_ndc = (A z + B) / -z in perspective, A z + B in
orthographic projection, z the view-space depth (negative in front of the camera).
"""

from typing import NamedTuple

import numpy as np

# The bounding sphere's radius is scaled by this: thick hairs reach past their strands' box.
SPHERE_MARGIN = 1.5


class FittedDepth(NamedTuple):
    projection: np.ndarray  # float64 [4, 4]: the viewport's, with its depth planes fitted to the hair
    planes: tuple           # (A, B) fitted, then (A, B) of the viewport's projection
    perspective: bool


def _planes(near, far, perspective):
    if perspective:
        return -(far + near) / (far - near), -2.0 * far * near / (far - near)
    return -2.0 / (far - near), -(far + near) / (far - near)


def _clip_range(a, b, perspective):
    """(near, far) distances of the planes (A, B)."""
    if perspective:
        return b / (a - 1.0), b / (a + 1.0)
    return (b + 1.0) / a, (b - 1.0) / a


def fitted_projection(projection, view, centre, radius, margin=SPHERE_MARGIN):
    """The projection [4, 4] with its near and far planes moved in to the sphere (world `centre`,
    `radius`) seen through the view matrix [4, 4], never beyond the projection's own planes (what the
    viewport clips stays clipped). Unchanged where the sphere lies outside them."""
    matrix = np.array(projection, dtype=np.float64)
    perspective = bool(matrix[3, 2] != 0.0)
    a, b = float(matrix[2, 2]), float(matrix[2, 3])
    near, far = _clip_range(a, b, perspective)
    depth = -float((np.asarray(view, np.float64) @ np.append(np.asarray(centre, np.float64), 1.0))[2])
    fitted_near, fitted_far = max(near, depth - margin * radius), min(far, depth + margin * radius)
    if not fitted_far > fitted_near:
        return FittedDepth(matrix, (a, b, a, b), perspective)
    fitted_a, fitted_b = _planes(fitted_near, fitted_far, perspective)
    fitted = matrix.copy()
    fitted[2, 2], fitted[2, 3] = fitted_a, fitted_b
    return FittedDepth(fitted, (fitted_a, fitted_b, a, b), perspective)


def viewport_depth(depth, fitted):
    """The viewport's window depth in [0, 1] of points at fitted window depth `depth` (array): what
    hair_layer.glsl computes per pixel."""
    fitted_a, fitted_b, a, b = fitted.planes
    ndc = 2.0 * np.asarray(depth, np.float64) - 1.0
    if fitted.perspective:
        z = -fitted_b / (ndc + fitted_a)
        viewport_ndc = (a * z + b) / -z
    else:
        z = (ndc - fitted_b) / fitted_a
        viewport_ndc = a * z + b
    return np.clip(0.5 * viewport_ndc + 0.5, 0.0, 1.0)
