"""The hair's world occlusion grid (hairlod.world_occlusion) as the 3D texture world_occlusion.glsl reads."""

import gpu
import numpy as np

from ...self_shadow import WORLD_DIRECTIONS

SAMPLER_SLOT = 12  # of "world_depths" (the shading takes 0-9, the hair layer's and the pulled strips' 10-11)
GROUPS = -(-len(WORLD_DIRECTIONS) // 4)  # RGBA texels per voxel: the 14 depths in 4 groups along z


def declare(info):
    info.sampler(SAMPLER_SLOT, 'FLOAT_3D', "world_depths")


def texture(occlusion):
    """A 3D RGBA32F texture of nx x ny x (4 nz) texels: slice g nz + z holds the depths of directions
    4 g .. 4 g + 3 at voxels (x, y, z) (the last group's last two channels 0; world_occlusion.glsl reads
    the 4 groups). None: a 1 x 1 x 4 texture
    of zeros, bound where the frame has no grid (world_grid_lower.w = 0, never read)."""
    if occlusion is None:
        depths = np.zeros((len(WORLD_DIRECTIONS), 1, 1, 1), np.float32)
    else:
        depths = np.asarray(occlusion.optical_depths, np.float32)
    nx, ny, nz = depths.shape[1:]
    channels = np.zeros((4 * GROUPS, nx, ny, nz), np.float32)
    channels[:len(depths)] = depths
    # [group, channel, x, y, z] -> texels [group, z, y, x, channel], x fastest.
    texels = np.ascontiguousarray(channels.reshape(GROUPS, 4, nx, ny, nz).transpose(0, 4, 3, 2, 1))
    return gpu.types.GPUTexture((nx, ny, GROUPS * nz), format='RGBA32F',
                                data=gpu.types.Buffer('FLOAT', texels.size, texels.ravel()))
