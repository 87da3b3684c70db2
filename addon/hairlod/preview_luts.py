"""The aggregated BCSDF's baked tables laid out as the viewport shader reads them (no bpy).

The shader (addon/hairlod/blender/preview/shaders/aggregated_bcsdf.glsl) takes three RGBA float
textures whose rows are the baked quantities, one RGB quantity per row, and a few lobe constants:

  fiber:       rows A_R, A_TT, A_D over theta_o in [0, pi/2]                       (Huang et al. 2025, Eq. 1)
  dual:        rows a_f, a_b, A_1, A_3, Delta_b, sigma_b, sigma_f^2 over theta_d   (Zinke et al. 2008; Eq. 9)
  aggregated:  blocks a_F^(n-1), A_1+, B^ budget, each n_samples rows over (theta_d, n in [1, n_max]) (Eq. 7, 10)

Every table comes straight from the C++ bake (cpp/src/bcsdf/bake.cpp), so the shader and
``hairlod.bcsdf.bake`` read the same numbers.
"""

from dataclasses import dataclass

import numpy as np

from . import _core
from .bcsdf import DEFAULT_TABLE_SAMPLES, as_params

__all__ = ["ShaderTables", "shader_tables"]

_ROWS = {
    "fiber_attenuation": ("A_R", "A_TT", "A_D"),
    "dual_scattering": ("a_f", "a_b", "A_1", "A_3", "delta_b", "sigma_b", "sigma_f2"),
    "aggregated_attenuation": ("a_F_n", "A_1plus", "budget"),
}


@dataclass(frozen=True)
class ShaderTables:
    fiber: np.ndarray        # float32 [3, theta_samples, 4]
    dual: np.ndarray         # float32 [7, theta_samples, 4]
    aggregated: np.ndarray   # float32 [3 n_samples, theta_samples, 4]
    lobe_shapes: tuple       # R shift, R variance, TT shift, TT variance (theta_i measure)
    lut_constants: tuple     # TT azimuthal variance, n_max

    @property
    def nbytes(self):
        return self.fiber.nbytes + self.dual.nbytes + self.aggregated.nbytes


def _rows(table, quantities):
    """[rows, width, 4]: each RGB quantity of a baked table as rows (alpha 1), blocks of the table's
    height per quantity."""
    values = np.asarray(table["values"], dtype=np.float32)  # [height, width, channels]
    channels = list(table["channels"])
    blocks = []
    for quantity in quantities:
        first = channels.index(f"{quantity}.R")
        rgb = values[:, :, first:first + 3]
        blocks.append(np.concatenate([rgb, np.ones(rgb.shape[:2] + (1,), np.float32)], axis=2))
    return np.ascontiguousarray(np.concatenate(blocks, axis=0))


def shader_tables(params, max_hair_count=64.0, theta_samples=64, hair_count_samples=64,
                  table_samples=DEFAULT_TABLE_SAMPLES):
    """Bakes the aggregated BCSDF's tables for `params` (a HairParams or dict) for hair counts up to
    `max_hair_count` and returns them in the shader's layout."""
    params = as_params(params)
    tables = {table["name"]: table for table in _core.bcsdf_bake(
        params, theta_samples=int(theta_samples), hair_count_samples=int(hair_count_samples),
        max_hair_count=float(max_hair_count), table_samples=int(table_samples), tables=["aggregated"])}
    lobes = _core.fiber_rtd_lobes(params)
    n_axis = tables["aggregated_attenuation"]["axes"][1]
    return ShaderTables(
        fiber=_rows(tables["fiber_attenuation"], _ROWS["fiber_attenuation"]),
        dual=_rows(tables["dual_scattering"], _ROWS["dual_scattering"]),
        aggregated=_rows(tables["aggregated_attenuation"], _ROWS["aggregated_attenuation"]),
        lobe_shapes=(lobes["r_shift"], lobes["r_variance"], lobes["tt_shift"], lobes["tt_variance"]),
        lut_constants=(lobes["tt_azimuthal_variance"], float(n_axis["range"][1])))
