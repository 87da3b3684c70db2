"""Hair LoD assets: guides, L0 clusters, thick elliptical hairs per level, skinning and selection.

Implements hair-lod-aggregated-bcsdf.txt Sec. 5 over the C++ core (no bpy). Arrays are numpy copies.
"""

from dataclasses import dataclass

import numpy as np

from . import _core

__all__ = ["LodAsset", "ThickLevel", "build_lod"]


@dataclass(frozen=True)
class ThickLevel:
    """One level of thick hairs at rest; per-control-point arrays are [hairs, n_c, ...]."""

    centres: np.ndarray        # float32 [H, n_c, 3]
    major_axis: np.ndarray     # float32 [H, n_c, 3], unit
    minor_axis: np.ndarray     # float32 [H, n_c, 3], unit
    radii: np.ndarray          # float32 [H, n_c, 2] (major, minor)
    density: np.ndarray        # float32 [H, n_c], rho = n_total r^2 / (|r_A| |r_B|) (Sec. 4)
    corner_strands: np.ndarray  # int32 [H, n_c, 4], strands whose control point k is a corner
    n_total: np.ndarray        # int32 [H], member strands
    parent: np.ndarray         # int32 [H], hair one level coarser (-1 on L0)
    membership: np.ndarray     # int32 [strands], hair of this level holding each strand
    cluster_first: np.ndarray  # int32 [clusters + 1], hairs of L0 cluster c: [first[c], first[c + 1])
    coverage: float            # fraction of member control points inside their ellipse
    mean_area: float           # mean pi r_A r_B


class LodAsset:
    """A built LoD hierarchy; the strands themselves are the finest level (index len(levels))."""

    def __init__(self, core_asset):
        self._core = core_asset
        self.levels = [ThickLevel(**level) for level in core_asset.thick_levels()]

    guide_count = property(lambda self: self._core.guide_count)
    cluster_count = property(lambda self: self._core.cluster_count)
    strand_count = property(lambda self: self._core.strand_count)
    control_points = property(lambda self: self._core.control_points)
    guide_strands = property(lambda self: self._core.guide_strands)
    rest_guides = property(lambda self: self._core.rest_guides)
    cluster_guides = property(lambda self: self._core.cluster_guides)
    timings = property(lambda self: self._core.timings)
    memory_bytes = property(lambda self: self._core.memory_bytes)

    @property
    def coverage(self):
        """Coverage per thick level (target >= 0.95)."""
        return [level.coverage for level in self.levels]

    @property
    def area_ratios(self):
        """Mean cross-section area of each level over the next finer one (about 4 by design)."""
        return [coarse.mean_area / fine.mean_area for coarse, fine in zip(self.levels, self.levels[1:])]

    def skin(self, deformed_guides):
        """Strands and thick hairs for guides [G, n_c, 3]: dict with 'strands' (Strands), 'levels'
        (centres, tangents, major/minor semi-axes, corners) and 'cluster_bounds' [C, 4]."""
        return self._core.skin(np.asarray(deformed_guides, dtype=np.float32))

    def select(self, view, projection, viewport_size, width_px=2.0, previous=None, guides=None):
        """LoD selection from column-major-convention 4x4 matrices (numpy rows are matrix rows,
        as Blender's Matrix converts): the initial selection, or Eq. 16 from `previous`."""
        guides = self.rest_guides if guides is None else np.asarray(guides, dtype=np.float32)
        return self._core.select(guides, np.asarray(view, dtype=np.float32), np.asarray(projection, dtype=np.float32),
                                 tuple(float(v) for v in viewport_size), float(width_px), previous)


def build_lod(strands, guides=256, levels=6, control_points=16, seed=0, ellipse_coverage=0.95):
    """Builds an LodAsset from Strands (Sec. 5.1); raises ValueError on invalid input."""
    return LodAsset(_core.build_lod(strands, guides=guides, levels=levels, control_points=control_points,
                                    seed=seed, ellipse_coverage=ellipse_coverage))
