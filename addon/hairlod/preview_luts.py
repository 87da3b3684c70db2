"""The aggregated BCSDF's baked tables laid out as the viewport shader reads them (no bpy).

The shader (addon/hairlod/blender/preview/shaders/aggregated_bcsdf.glsl) takes three RGBA float
textures whose rows are the baked quantities, one RGB quantity per row, and a few lobe constants:

  fiber:       rows A_R, A_TT, A_D over theta_o in [0, pi/2]                       (Huang et al. 2025, Eq. 1)
  dual:        rows a_f, a_b, A_1, A_3, Delta_b, sigma_b, sigma_f^2, beta_f^2 over theta_d (Zinke et al. 2008; Huang 2025 Eq. 9)
  aggregated:  blocks a_F^(n-1), A_1+, B^ budget, each n_samples rows over (theta_d, n in [1, n_max])
               (Huang 2025 Eq. 7, 10)

Every table comes straight from the C++ bake (cpp/src/bcsdf/bake.cpp), so the shader and
``hairlod.bcsdf_bake.bake`` read the same numbers.
"""

from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from . import _core
from .bcsdf_bake import DEFAULT_TABLE_SAMPLES
from .hair_params import as_params, params_to_dict

__all__ = ["ShaderTables", "SrbfTables", "shader_tables", "srbf_tables", "theta_nodes", "uniform_world_response"]

_ROWS = {
    "fiber_attenuation": ("A_R", "A_TT", "A_D"),
    "dual_scattering": ("a_f", "a_b", "A_1", "A_3", "delta_b", "sigma_b", "sigma_f2", "beta_f2"),
    "aggregated_attenuation": ("a_F_n", "A_1plus", "budget"),
}


@dataclass(frozen=True)
class ShaderTables:
    fiber: np.ndarray        # float32 [3, theta_samples, 4]
    dual: np.ndarray         # float32 [8, theta_samples, 4]
    aggregated: np.ndarray   # float32 [3 n_samples, theta_samples, 4]
    lobe_shapes: tuple       # R shift, R variance, TT shift, TT variance (theta_i measure)
    lut_constants: tuple     # TT azimuthal variance, n_max

    @property
    def nbytes(self):
        return self.fiber.nbytes + self.dual.nbytes + self.aggregated.nbytes


# The tables of the last few (parameters, sampling) pairs, shared by every preview in the process: an LoD
# built again, its preview switched off and on, or another object with the same material draws its
# first frame without baking again (the BCSDF tables and the world's response took 0.1-0.25 s each of
# the first frame after a 100k-strand build in Blender). The arrays are read-only, since callers share them.
CACHED_TABLES = 8
_cache = OrderedDict()


def _cached(key, make):
    """make()'s value for `key`, made once while it stays among the CACHED_TABLES last used."""
    if key in _cache:
        _cache.move_to_end(key)
        return _cache[key]
    value = make()
    _cache[key] = value
    while len(_cache) > CACHED_TABLES:
        _cache.popitem(last=False)
    return value


def _read_only(array):
    array.setflags(write=False)
    return array


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
    `max_hair_count` and returns them in the shader's layout (cached: see CACHED_TABLES)."""
    params = as_params(params)
    sampling = (float(max_hair_count), int(theta_samples), int(hair_count_samples), int(table_samples))
    return _cached(("shader", repr(params_to_dict(params)), sampling), lambda: _bake_shader_tables(params, *sampling))


def _bake_shader_tables(params, max_hair_count, theta_samples, hair_count_samples, table_samples):
    tables = {table["name"]: table for table in _core.bcsdf_bake(
        params, theta_samples=theta_samples, hair_count_samples=hair_count_samples,
        max_hair_count=max_hair_count, table_samples=table_samples, tables=["aggregated"])}
    lobes = _core.fiber_rtd_lobes(params)
    n_axis = tables["aggregated_attenuation"]["axes"][1]
    return ShaderTables(
        fiber=_read_only(_rows(tables["fiber_attenuation"], _ROWS["fiber_attenuation"])),
        dual=_read_only(_rows(tables["dual_scattering"], _ROWS["dual_scattering"])),
        aggregated=_read_only(_rows(tables["aggregated_attenuation"], _ROWS["aggregated_attenuation"])),
        lobe_shapes=(lobes["r_shift"], lobes["r_variance"], lobes["tt_shift"], lobes["tt_variance"]),
        lut_constants=(lobes["tt_azimuthal_variance"], float(n_axis["range"][1])))


@dataclass(frozen=True)
class SrbfTables:
    """The hair's response to one SRBF light of bandwidth ``lam`` (Xu et al. 2011, Eq. 2 and 11-14),
    for shaders/srbf_world.glsl. ``response`` [samples^2 + 1, samples, 4]: row j samples + o holds
    theta_j node j and theta_o node o (both over [-pi/2, pi/2]) across |phi_o - phi_j| in [0, pi];
    the last row holds the response to a uniform unit world across theta_o. The theta nodes are
    theta_nodes(samples), the phi nodes uniform."""
    response: np.ndarray
    lam: float

    @property
    def samples(self):
        return self.response.shape[1]

    @property
    def nbytes(self):
        return self.response.nbytes


def theta_nodes(samples):
    """The theta nodes of SrbfTables: theta = pi/2 sin(pi s / 2) for s uniform in [-1, 1], denser
    towards the grazing angles, where the response changes fastest (the Marschner energy
    normalisation and the lobes' cos(theta) factors). srbf_world.glsl inverts the map."""
    return 0.5 * np.pi * np.sin(0.5 * np.pi * np.linspace(-1.0, 1.0, samples))


def srbf_tables(params, lam, samples=20, lobes=True):
    """Tabulates the hair's response to one unit SRBF light of bandwidth `lam` over the light's and the
    view's angles in the fibre frame: hairlod.bcsdf.srbf_single_scattering (the Marschner fibre of
    `params`, Xu et al. 2011 Eq. 11-14); the response depends only on theta_o, theta_j and
    |phi_o - phi_j| (the fibre is symmetric about its normal plane's azimuth), so any lobe direction is a
    lookup. About 1 s at 20 samples, where trilinear interpolation stays within about 3% of the peak
    response (tests/ui/test_bcsdf_shader.py). The last row, the response to a uniform unit world, is the
    material's own fibre's directional albedo (uniform_world_response): exact, where Xu's closed form on
    the Marschner fibre read 0.94-0.96 of it at normal incidence and down to 0.4 at grazing views.
    Without `lobes` (a world of its uniform term alone) only the last row is computed, in about 0.02 s,
    and the lobes' rows hold zeros, which a world with no lobes never reads. Cached: see CACHED_TABLES."""
    params = as_params(params)
    lam = float(lam)
    if not (np.isfinite(lam) and lam > 0.0):
        raise ValueError(f"SRBF bandwidth must be finite and > 0, got {lam}")
    samples = int(samples)
    if samples < 2:
        raise ValueError(f"srbf table samples must be >= 2, got {samples}")
    return _cached(("srbf", repr(params_to_dict(params)), lam, samples, bool(lobes)),
                   lambda: _tabulate_srbf(params, lam, samples, bool(lobes)))


def _tabulate_srbf(params, lam, samples, lobes):
    from .bcsdf import srbf_single_scattering

    theta = theta_nodes(samples)
    phi = np.linspace(0.0, np.pi, samples)
    theta_o, delta_phi = np.meshgrid(theta, phi, indexing="ij")
    wo = np.stack([np.sin(theta_o), np.cos(theta_o) * np.cos(delta_phi), np.cos(theta_o) * np.sin(delta_phi)],
                  axis=-1).reshape(-1, 3)
    response = np.ones((samples * samples + 1, samples, 4), np.float32)
    if not lobes:
        response[:-1, :, :3] = 0.0
    for j, theta_j in enumerate(theta if lobes else ()):
        light = {"directions": [[np.sin(theta_j), np.cos(theta_j), 0.0]], "lambdas": [lam],
                 "coefficients": [[1.0, 1.0, 1.0]]}
        values = srbf_single_scattering(params, light, wo)
        response[j * samples:(j + 1) * samples, :, :3] = values.reshape(samples, samples, 3)
    response[-1, :, :3] = uniform_world_response(params, theta)
    return SrbfTables(response=_read_only(np.ascontiguousarray(response)), lam=lam)


# theta_o samples of the fibre's attenuation table: those of FiberRtdBcsdf's own table
# (cpp/src/bcsdf/fiber_rtd.cpp), so that interpolating this one reads its values.
_ALBEDO_SAMPLES = 257


def uniform_world_response(params, theta_o):
    """The radiance a hair sends towards theta_o (radians, any shape) under a uniform unit world,
    float64 [..., 3]: the integral of S(wi, wo) cos(theta_i) over the sphere, the directional albedo of
    the material's fibre (the white furnace; the path tracer's Chiang fibre, and for a Huang material
    the Chiang fibre fitted to it). It is the fibre's A_R + A_TT + A_D at theta_o (the R / TT / D fibre
    of Huang et al. 2025 Eq. 1, with the Chiang fibre's h-averaged attenuations: bake's
    fiber_attenuation), even in theta_o."""
    baked = {table["name"]: table for table in _core.bcsdf_bake(
        as_params(params), theta_samples=_ALBEDO_SAMPLES, hair_count_samples=2, max_hair_count=1.0, table_samples=3,
        tables=["aggregated"])}
    albedo = _rows(baked["fiber_attenuation"], _ROWS["fiber_attenuation"])[:, :, :3].sum(axis=0, dtype=np.float64)
    nodes = np.linspace(0.0, 0.5 * np.pi, _ALBEDO_SAMPLES)
    at = np.minimum(np.abs(np.asarray(theta_o, np.float64)), 0.5 * np.pi)
    return np.stack([np.interp(at, nodes, albedo[:, channel]) for channel in range(3)], axis=-1)
