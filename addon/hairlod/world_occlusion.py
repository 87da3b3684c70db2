"""How much of the world each point of the hair sees past the hair itself (no bpy): the strands'
density on a grid, and the optical depth from every voxel out to the world along each of
self_shadow.WORLD_DIRECTIONS.

The preview's world term averaged the transmittance over 14 directions through the hair-volume
ellipsoid (self_shadow.world_transmittance): a uniform medium filling the strands' bounding box. Real
hair is not that: a head of hair is a shell around an empty inside, and its tips hang below the box's
inscribed ellipsoid, so the ellipsoid left the tips open to the whole sky and filled the shell's
inside with strands (docs/preview.md, "Where the dense hair's spread comes from"). Here the strands
themselves say where the hair is. Each strand's segments are sampled at most half a voxel apart, and
each sample adds its share of the segment's projected area, 2 r l, to the voxels around it (trilinear
weights), per unit volume: the extinction of fibres crossed at right angles, as self_shadow's. A fibre
crossed at an angle theta to its tangent shows 2 r |sin theta| per unit length (light along the strands
passes them), so the samples also add their tangents' second moments t t^T, and the extinction towards
a direction d is the density times sqrt(1 - d^T <t t^T> d), the root of the voxel's mean sin^2 theta
(the mean |sin theta| where a voxel's strands run alike, as hair's do nearby; 4 % over it for strands
in every direction). The optical depth towards the world along d is the integral of that extinction
from the voxel outwards; with cubic voxels each of the 14 directions (6 axes, 8 cube diagonals) steps
from voxel centre to voxel centre, so one sweep per direction gives every voxel's depth exactly on the
grid (trapezoids, tau(c) = L (sigma(c) + sigma(c + delta)) / 2 + tau(c + delta), L the step's length;
0 beyond the grid).

The preview reads the 14 depths at a shading point by trilinear filtering of a 3D texture
(shaders/world_occlusion.glsl); optical_depths() here is the same lookup in float64, the reference
tests/ui/test_bcsdf_shader.py compares it with.
"""

from dataclasses import dataclass

import numpy as np

from . import _core
from .self_shadow import WORLD_DIRECTIONS, strand_arrays

__all__ = ["GRID_RESOLUTION", "MAX_SAMPLES", "SAMPLE_SPACING", "WorldOcclusion", "moved_occlusion", "optical_depths",
           "strands_occlusion", "world_occlusion", "world_transmittance"]

# Voxels along the hair's largest extent. A head of hair is a shell a tenth to a fifth of its size
# thick: 48 voxels put 5-10 across it, and the sweep and the texture stay small (48 x 48 x 40 voxels
# of 16 depths: 5.9 MB in float32).
GRID_RESOLUTION = 48
# The samples splatted, each at most SAMPLE_SPACING voxels from the next along its strand: at most
# MAX_SAMPLES of them, from every k-th strand (each standing for k): 250k samples put tens in every voxel a
# dense head of hair fills, and keep the grid of 100k strands of 17 points to 45 ms of the first frame (15
# ms of it the samples' splat in C++; numpy's took 0.15 s in all).
SAMPLE_SPACING = 0.5
MAX_SAMPLES = 250_000


@dataclass(frozen=True)
class WorldOcclusion:
    lower: np.ndarray           # float64 [3]: the grid's lower corner, object space
    extent: np.ndarray          # float64 [3]: the grid's size per axis, object space (> 0)
    optical_depths: np.ndarray  # float32 [14, nx, ny, nz]: per WORLD_DIRECTIONS, at the voxels' centres, strength 1
    depth_factor: float = 1.0   # the depths' factor (moved_occlusion: hair stretched from its rest)

    @property
    def shape(self):
        return self.optical_depths.shape[1:]


def world_occlusion(points, offsets, radius, resolution=GRID_RESOLUTION, max_samples=MAX_SAMPLES):
    """The WorldOcclusion of strands given as points [N, 3], offsets [C + 1] and radius [N] (the
    layout of hairlod.Strands), on a grid of `resolution` voxels along their largest extent (plus
    one on every side, which takes the density the points on the box's faces spread outwards), from
    at most `max_samples` samples along the strands (taken in float32, as hairlod.Strands holds points)."""
    points, offsets, radius = strand_arrays(points, offsets, radius, "world occlusion")
    if np.any(np.diff(offsets) < 1):
        raise ValueError("world occlusion: offsets must rise (every strand holds a point)")
    return _occlusion(points, offsets, radius, points.min(axis=0), points.max(axis=0), resolution, max_samples)


def strands_occlusion(strands, resolution=GRID_RESOLUTION, max_samples=MAX_SAMPLES):
    """The WorldOcclusion of a hairlod.Strands (validated, finite): world_occlusion of its arrays, with
    the core's bounding box and no copy of them."""
    lower, upper = strands.bounding_box()
    return _occlusion(strands.points, np.asarray(strands.offsets, np.int64), strands.radius,
                      np.asarray(lower, np.float64), np.asarray(upper, np.float64), resolution, max_samples)


def _occlusion(points, offsets, radius, lower, upper, resolution, max_samples):
    """world_occlusion of valid arrays (float32 or float64) whose points lie in the box [lower, upper]."""
    if int(resolution) < 1 or int(max_samples) < 1:
        raise ValueError(f"world occlusion: resolution and max_samples must be >= 1, got {resolution}, {max_samples}")
    # The strands' density and their tangents' second moments (C++ core/strand_density.h): each segment
    # sampled at most half a voxel apart, each sample its share of the segment's projected area 2 r l (a
    # strand's segments are often longer than a voxel, 2.5 cm of 17-point strands against voxels of 0.8 cm,
    # and its points alone pile the density into planes), from every k-th strand, each standing for k.
    fields, voxel, _ = _core.strand_density(points, offsets, radius, lower, upper, int(resolution), int(max_samples),
                                            SAMPLE_SPACING)
    density, m = fields[0], fields[1:]
    mean_moments = m / np.where(density > 0.0, density, 1.0)
    depths = []
    for direction, grid_step in zip(WORLD_DIRECTIONS, _GRID_STEPS):
        # A fibre crossed at angle theta to its tangent shows 2 r |sin theta| per unit length: light along
        # the strands passes them. sin^2 = 1 - d^T <t t^T> d over the voxel's strands; the root of its mean
        # stands for the mean of |sin| (equal where a voxel's strands run alike, as hair's do nearby).
        along_d = (direction[0] ** 2 * mean_moments[0] + direction[1] ** 2 * mean_moments[1] +
                   direction[2] ** 2 * mean_moments[2] + 2.0 * (direction[0] * direction[1] * mean_moments[3] +
                   direction[0] * direction[2] * mean_moments[4] + direction[1] * direction[2] * mean_moments[5]))
        depths.append(_sweep(density * np.sqrt(np.clip(1.0 - along_d, 0.0, 1.0)), grid_step, voxel))
    return WorldOcclusion(lower=lower - voxel, extent=voxel * np.asarray(density.shape, np.float64),
                          optical_depths=np.stack(depths).astype(np.float32))


def moved_occlusion(rest, rest_box, box):
    """The WorldOcclusion of hair that moved or deformed, from its rest one and a box bounding it at
    rest and now ((lower, upper) pairs, as self_shadow.moved_volume takes): the grid moves with the
    box's centre and scales with its extents; the density falls as the volume grows and the paths
    grow with the mean scale. Exact for a translation; a rotation is seen through the axis-aligned box."""
    rest_lower, rest_upper = (np.asarray(v, np.float64) for v in rest_box)
    lower, upper = (np.asarray(v, np.float64) for v in box)
    rest_extent, extent = rest_upper - rest_lower, upper - lower
    scale = np.where(rest_extent > 0.0, extent / np.where(rest_extent > 0.0, rest_extent, 1.0), 1.0)
    scale = np.maximum(scale, 1e-3)  # a box collapsed to a plane keeps a finite grid
    rest_centre, centre = 0.5 * (rest_lower + rest_upper), 0.5 * (lower + upper)
    return WorldOcclusion(lower=centre + (rest.lower - rest_centre) * scale, extent=rest.extent * scale,
                          optical_depths=rest.optical_depths,
                          depth_factor=rest.depth_factor * float(np.mean(scale)) / float(np.prod(scale)))


def optical_depths(occlusion, points):
    """The optical depths [N, 14] (strength 1) towards the world along WORLD_DIRECTIONS at points
    [N, 3]: the grid's values at the voxels' centres, trilinear between them, clamped to the outer
    centres (a texture's linear filtering with clamp-to-edge)."""
    points = np.atleast_2d(np.asarray(points, dtype=np.float64))
    shape = np.asarray(occlusion.shape)
    cell = (points - occlusion.lower) / occlusion.extent * shape - 0.5
    cell = np.clip(cell, 0.0, shape - 1.0)
    base = np.minimum(np.floor(cell).astype(np.int64), np.maximum(shape - 2, 0))
    frac = cell - base
    result = np.zeros((len(points), len(WORLD_DIRECTIONS)))
    for corner in np.ndindex(2, 2, 2):
        index = np.minimum(base + corner, shape - 1)
        weight = np.prod(np.where(np.asarray(corner) == 1, frac, 1.0 - frac), axis=1)
        result += weight[:, None] * occlusion.optical_depths[:, index[:, 0], index[:, 1], index[:, 2]].T
    return result * occlusion.depth_factor


def world_transmittance(points, occlusion, strength, keep=None):
    """The share of a uniform world's light that reaches points [N, 3] past the hair: exp(-strength
    tau) over the 14 directions, averaged; with `keep` (per channel [3] or per direction and channel
    [14, 3], as self_shadow.world_transmittance takes it) exp(-keep strength tau) per channel, [N, 3]."""
    if not np.isfinite(strength) or strength < 0.0:
        raise ValueError(f"world transmittance: strength must be finite and >= 0, got {strength}")
    tau = strength * optical_depths(occlusion, points)
    if keep is None:
        return np.exp(-tau).mean(axis=1)
    keep = np.asarray(keep, dtype=np.float64)
    if keep.shape not in ((3,), (len(WORLD_DIRECTIONS), 3)):
        raise ValueError(f"world transmittance: keep must have shape [3] or [{len(WORLD_DIRECTIONS)}, 3], "
                         f"got {list(keep.shape)}")
    keep = np.broadcast_to(keep, (len(WORLD_DIRECTIONS), 3))
    return np.exp(-tau[:, :, None] * keep[None, :, :]).mean(axis=1)


# WORLD_DIRECTIONS as steps between neighbouring voxels: the axes and the cube diagonals.
_GRID_STEPS = np.rint(WORLD_DIRECTIONS / np.abs(WORLD_DIRECTIONS).max(axis=1, keepdims=True)).astype(np.int64)


def _sweep(sigma, step, voxel):
    """The optical depth at every voxel towards `step` (integer components in -1..1), by trapezoids
    from voxel centre to voxel centre, 0 past the grid."""
    length = voxel * float(np.linalg.norm(step))
    padded = np.pad(sigma, 1)
    tau = np.zeros_like(padded)
    axis = int(np.flatnonzero(step)[0])
    others = [int(step[b]) for b in range(3) if b != axis]
    s, t = np.moveaxis(padded, axis, 0), np.moveaxis(tau, axis, 0)
    along = int(step[axis])
    n = s.shape[0]
    rows = slice(1 + others[0], s.shape[1] - 1 + others[0])
    columns = slice(1 + others[1], s.shape[2] - 1 + others[1])
    for i in (range(n - 2, 0, -1) if along > 0 else range(1, n - 1)):
        t[i, 1:-1, 1:-1] = 0.5 * length * (s[i, 1:-1, 1:-1] + s[i + along, rows, columns]) + t[i + along, rows, columns]
    return tau[1:-1, 1:-1, 1:-1]
