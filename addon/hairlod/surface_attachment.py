"""Curves attached to a triangle mesh by UV coordinates, moved with it as Blender's Deform Curves on
Surface node moves hair on an animated head (cpp/include/hairlod/curves/surface_attachment.h): every
curve turns and moves rigidly with the frame of its root point on its triangle."""

import numpy as np

from . import _core


class SurfaceFollow:
    """Curves bound by their root UV coordinates [N, 2] to a mesh given as arrays: corner_uvs [C, 2]
    (its UV map), triangles [T, 3] (corner indices), corner_verts [C], at the reference pose
    positions [V, 3] and corner_normals [C, 3]; surface_to_curves [4, 4] maps the mesh's object space
    into the curves' (numpy rows are matrix rows). Curves whose UV lies in no triangle, or inside two,
    stay where they are, as Blender leaves them."""

    def __init__(self, root_uvs, corner_uvs, triangles, corner_verts, positions, corner_normals, surface_to_curves):
        self.vertex_count, self.corner_count = len(positions), len(corner_verts)
        self._core = _core.SurfaceFollow(np.asarray(root_uvs, np.float32), np.asarray(corner_uvs, np.float32),
                                         np.asarray(triangles, np.int32), np.asarray(corner_verts, np.int32),
                                         np.asarray(positions, np.float32), np.asarray(corner_normals, np.float32),
                                         np.asarray(surface_to_curves, np.float32))

    @property
    def bound(self):
        """bool [N]: the curves that move with the surface."""
        return self._core.bound

    def transforms(self, positions, corner_normals, surface_to_curves, out=None):
        """float32 [N, 3, 4]: per curve the affine map [R | t] (rows) from the reference pose to the pose
        of the same mesh with these positions [V, 3] and corner normals [C, 3] (`apply` moves points by
        them). With `out` (a float32, C-contiguous [N, 3, 4] array) they are written there and `out` is
        returned: an array kept from pose to pose is memory already mapped. Raises ValueError when their
        counts are not the reference pose's, or `out` is not such an array."""
        return self._core.transforms(np.asarray(positions, np.float32), np.asarray(corner_normals, np.float32),
                                     np.asarray(surface_to_curves, np.float32), out)


def apply(transforms, points):
    """Points [N, K, 3] of N curves moved by their transforms [N, 3, 4] (float32)."""
    points = np.asarray(points, np.float32)
    return np.einsum("nij,nkj->nki", transforms[:, :, :3], points) + transforms[:, None, :, 3]
