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

__all__ = ["ShaderTables", "SrbfTables", "forward_share", "lobe_responses", "material_fibre_rows", "scattering_albedo", "shader_tables", "srbf_lookup",
           "srbf_tables", "theta_nodes", "uniform_world_response"]

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
    material: np.ndarray     # float32 [4 theta_samples, phi_samples + 1, 4]: material_fibre_rows
    material_lobes: tuple    # TRT shift, TRT variance (TRRT+: no shift, the same variance)

    @property
    def nbytes(self):
        return self.fiber.nbytes + self.dual.nbytes + self.aggregated.nbytes + self.material.nbytes


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
    material, material_shapes = material_fibre_rows(params, theta_samples=theta_samples)
    n_axis = tables["aggregated_attenuation"]["axes"][1]
    return ShaderTables(
        fiber=_read_only(_rows(tables["fiber_attenuation"], _ROWS["fiber_attenuation"])),
        dual=_read_only(_rows(tables["dual_scattering"], _ROWS["dual_scattering"])),
        aggregated=_read_only(_rows(tables["aggregated_attenuation"], _ROWS["aggregated_attenuation"])),
        lobe_shapes=(lobes["r_shift"], lobes["r_variance"], lobes["tt_shift"], lobes["tt_variance"]),
        lut_constants=(lobes["tt_azimuthal_variance"], float(n_axis["range"][1])),
        material=_read_only(material), material_lobes=tuple(float(x) for x in material_shapes[2]))


def material_fibre_rows(params, theta_samples=64, phi_samples=64):
    """The material's Chiang fibre in the far field as the preview's shader reads it, and its lobes'
    (shift, variance): float32 [4 theta_samples, phi_samples + 1, 4], row p theta_samples + j holding lobe p's
    (R, TT, TRT, TRRT+) weight times its azimuthal part N_p (d'Eon et al. 2011 Sec. 4, C++
    far_field_azimuthal_table) at theta_o = (pi / 2) j / (theta_samples - 1) across phi = pi k /
    (phi_samples - 1), and in its last texel N_p's mean over phi, A_p / (2 pi), towards which the thick
    hairs' forward scatterings spread it (aggregated_bcsdf.glsl). The fibre is sum_p M_p N_p / cos(theta_i)."""
    values, shapes = _core.chiang_far_field_table(as_params(params), theta_samples=theta_samples, phi_samples=phi_samples)
    # Trapezoids over the nodes of [0, pi] (N_p is even in phi): the mean over the circle.
    weight = np.full(phi_samples, 1.0 / (phi_samples - 1))
    weight[[0, -1]] *= 0.5
    mean = np.einsum("ptkc,k->ptc", values, weight)
    rows = np.concatenate([values, mean[:, :, None, :]], axis=2).reshape(4 * theta_samples, phi_samples + 1, 3)
    return (np.concatenate([rows, np.ones(rows.shape[:2] + (1,))], axis=2).astype(np.float32),
            [tuple(shape) for shape in shapes])


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


def forward_share(tables, sin_theta):
    """What aggregated_bcsdf.glsl's forward_share reads from `tables` (ShaderTables), in float64: a_f, the
    share of light a strand passes on forwards, at the inclinations asin(sin_theta) of the light to the
    strand, linear between the dual table's nodes over [-pi/2, pi/2] and clamped to [1e-4, 1]; [..., 3]."""
    a_f = np.asarray(tables.dual, np.float64)[0, :, :3]
    theta = np.arcsin(np.clip(np.asarray(sin_theta, np.float64), -1.0, 1.0))
    nodes = np.linspace(-0.5 * np.pi, 0.5 * np.pi, len(a_f))
    return np.clip(np.stack([np.interp(theta, nodes, a_f[:, c]) for c in range(3)], axis=-1), 1e-4, 1.0)


def scattering_albedo(tables):
    """The share of the light a strand does not pass on forwards that it scatters rather than absorbs,
    per channel, over every direction in the dual table: rho = int a_b cos(theta) / int (1 - a_f) cos(theta),
    theta over [-pi/2, pi/2] (the inclinations of directions uniform over the sphere), a_f and a_b the shares
    a strand scatters into the forward and the backward half-space (Zinke et al. 2008 Sec. 4.2), trapezoids
    over the table's nodes; float64 [3]. 1 for a fibre that absorbs nothing (a_f + a_b = 1), 0 for one that
    scatters only forwards. The preview's world term takes it as the albedo of the hair around a point
    (self_shadow.scattered_share)."""
    dual = np.asarray(tables.dual, np.float64)
    theta = np.linspace(-0.5 * np.pi, 0.5 * np.pi, dual.shape[1])
    # Trapezoid weights of the uniform nodes times cos(theta) (numpy 2 renamed trapz; this needs neither).
    weight = np.cos(theta)[:, None] * np.gradient(theta)[:, None]
    weight[[0, -1]] *= 0.5
    back = np.sum(weight * dual[1, :, :3], axis=0)
    lost = np.sum(weight * (1.0 - dual[0, :, :3]), axis=0)
    return np.where(lost > 1e-12, back / np.maximum(lost, 1e-12), 1.0).clip(0.0, 1.0)


def srbf_lookup(tables, sin_o, sin_j=None, phi=None):
    """What shaders/srbf_world.glsl reads from `tables` (SrbfTables), in float64: the response to one unit
    lobe at sin(theta_j) `sin_j` for views at sin(theta_o) `sin_o` across their azimuth difference `phi`
    (radians in [0, pi]), trilinear over the nodes, [..., 3]; without `sin_j`, the uniform row at sin_o."""
    response = np.asarray(tables.response, np.float64)[..., :3]
    samples = response.shape[1]

    def node(sin_theta):  # srbf_theta_node: the inverse of theta_nodes, in node units
        s = np.arcsin(np.clip(np.arcsin(np.clip(sin_theta, -1.0, 1.0)) / (0.5 * np.pi), -1.0, 1.0)) / (0.5 * np.pi)
        return (0.5 * s + 0.5) * (samples - 1)

    def row(index, x):  # lut_row: linear across a row's nodes
        position = np.clip(x, 0.0, 1.0) * (samples - 1)
        k = np.minimum(position.astype(int), samples - 2)
        t = (position - k)[..., None]
        return (1.0 - t) * response[index, k] + t * response[index, k + 1]

    node_o = node(np.asarray(sin_o, np.float64))
    if sin_j is None:
        return row(np.full(node_o.shape, samples * samples), node_o / (samples - 1))
    node_j = np.broadcast_to(node(np.asarray(sin_j, np.float64)), node_o.shape)
    x = np.asarray(phi, np.float64) / np.pi
    o = np.minimum(node_o.astype(int), samples - 2)
    j = np.minimum(node_j.astype(int), samples - 2)
    u, v = (node_o - o)[..., None], (node_j - j)[..., None]
    index = j * samples + o
    low = (1.0 - u) * row(index, x) + u * row(index + 1, x)
    high = (1.0 - u) * row(index + samples, x) + u * row(index + samples + 1, x)
    return (1.0 - v) * low + v * high


def theta_nodes(samples):
    """The theta nodes of SrbfTables: theta = pi/2 sin(pi s / 2) for s uniform in [-1, 1], denser
    towards the grazing angles, where the response changes fastest (the fibre's attenuations near
    grazing and the lobes' cos(theta) factors). srbf_world.glsl inverts the map."""
    return 0.5 * np.pi * np.sin(0.5 * np.pi * np.linspace(-1.0, 1.0, samples))


def srbf_tables(params, lam, samples=20, lobes=True):
    """Tabulates the hair's response to one unit SRBF light of bandwidth `lam` (Xu et al. 2011, Eq. 2:
    the integral over the sphere of G(wi; w_j, lam) S(wi, wo) cos(theta_i)) over the light's and the
    view's angles in the fibre frame, integrated numerically (lobe_responses) for the R / TT / D fibre
    (Huang et al. 2025, Eq. 1 with the Chiang fibre's energies; the lights are shaded with the material's
    own fibre, whose far field C++ evaluates 11x slower: 0.24 s against 0.021 s for 20,000 pairs of brown
    hair of roughness 0.3):
    the response depends only on theta_o, theta_j and |phi_o - phi_j| (the fibre is symmetric about its
    normal plane's azimuth), so any lobe direction is a lookup (srbf_lookup, as the shader reads it).
    Against the same integral of the material's Chiang fibre it reads within 5 % of the peak response
    for brown hair of roughness 0.3 (within 12 % for light hair of roughness 0.15, where the fibres'
    lobes differ most); Xu 2011's closed form on the Marschner fibre (Eq. 11-14,
    hairlod.bcsdf.srbf_single_scattering), which the table held before, read 0.03-1.02 of the Chiang
    integrals. The last row, the response to a uniform unit world, is the fibre's directional albedo,
    the Chiang fibre's too (uniform_world_response). About 0.1 s at 20 samples for roughness 0.3, up to
    about 1.5 s for the smoothest fibres (finer quadrature grids). Without `lobes` (a world of its
    uniform term alone) only the last row is computed, in about 0.02 s, and the lobes' rows hold zeros,
    which a world with no lobes never reads. Cached: see CACHED_TABLES."""
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
    theta = theta_nodes(samples)
    response = np.ones((samples * samples + 1, samples, 4), np.float32)
    response[:-1, :, :3] = lobe_responses(params, lam, theta, np.linspace(0.0, np.pi, samples)) if lobes else 0.0
    response[-1, :, :3] = uniform_world_response(params, theta)
    return SrbfTables(response=_read_only(np.ascontiguousarray(response)), lam=lam)


# The quadrature grid of lobe_responses: steps of half the narrowest width it must resolve, at least
# and at most these many nodes over theta_i in [-pi/2, pi/2] and over phi_i in [0, pi] (the most: 1.3M
# evaluations of the fibre for a 20-node table, about 1.5 s).
_GRID_NODES = (48, 256)


def lobe_responses(params, lam, theta, phi):
    """The response to one unit SRBF light of bandwidth `lam` (Xu et al. 2011, Eq. 2), float64 [J * O, P,
    3]: row j * O + o holds the light at inclination theta[j] (O = len(theta)) and the view at theta[o],
    across their azimuth differences phi[p], in the fibre frame. The integral over the sphere of
    G(wi; w_j, lam) S(wi, wo) cos(theta_i), S the R / TT / D fibre (bcsdf model "fiber_rtd"), by the
    midpoint rule on a theta_i x phi_i grid whose steps are half the narrower of the fibre's
    longitudinal lobes (its TT variance, fiber_rtd_lobes) and the light's width lam / sqrt(2). The view
    sits at phi_o = 0 and S is even in phi_i, so S is evaluated on phi_i in [0, pi] and each node weighs
    the light at phi_i and at -phi_i."""
    from .bcsdf import evaluate

    params = as_params(params)
    theta = np.asarray(theta, np.float64)
    phi = np.asarray(phi, np.float64)
    shapes = _core.fiber_rtd_lobes(params)
    width = min(np.sqrt(min(shapes["r_variance"], shapes["tt_variance"])), lam / np.sqrt(2.0))
    low, high = _GRID_NODES
    theta_count = int(np.clip(np.ceil(np.pi / (0.5 * width)), low, high))
    phi_count = theta_count
    theta_i = (np.arange(theta_count) + 0.5) * np.pi / theta_count - 0.5 * np.pi
    phi_i = (np.arange(phi_count) + 0.5) * np.pi / phi_count
    cos_i, sin_i = np.cos(theta_i), np.sin(theta_i)
    # wi over the grid, wo at each theta node (phi_o = 0): S for every pair, times cos(theta_i) and the
    # solid angle cos(theta_i) d theta d phi.
    wi = np.stack([np.broadcast_to(sin_i[:, None], (theta_count, phi_count)), cos_i[:, None] * np.cos(phi_i),
                   cos_i[:, None] * np.sin(phi_i)], axis=-1).reshape(-1, 3)
    wo = np.stack([np.sin(theta), np.cos(theta), np.zeros_like(theta)], axis=1)
    pairs = len(wi)
    scattered = evaluate("fiber_rtd", params, np.tile(wi, (len(theta), 1)), np.repeat(wo, pairs, axis=0))
    weight = (cos_i * cos_i * (np.pi / theta_count) * (np.pi / phi_count))[:, None]
    # [theta_i, phi_i, view * channel]
    scattered = (scattered.reshape(len(theta), theta_count, phi_count, 3).astype(np.float64) * weight[None, :, :, None])
    scattered = scattered.transpose(1, 2, 0, 3).reshape(theta_count, phi_count, len(theta) * 3)
    sin_j, cos_j = np.sin(theta)[:, None, None], np.cos(theta)[:, None, None]
    sharpness = 2.0 / (lam * lam)
    result = np.zeros((len(theta) * len(phi), len(theta) * 3))
    for row in range(theta_count):
        # G at (theta_i, +-phi_i) for every light (theta_j, phi_p): [J, P, phi_i] -> [J * P, phi_i].
        along = sin_i[row] * sin_j - 1.0
        across = cos_i[row] * cos_j
        lights = (np.exp(sharpness * (along + across * np.cos(phi_i[None, None, :] - phi[None, :, None]))) +
                  np.exp(sharpness * (along + across * np.cos(phi_i[None, None, :] + phi[None, :, None]))))
        result += lights.reshape(len(theta) * len(phi), phi_count) @ scattered[row]
    # [J, P, O, 3] -> rows j * O + o, columns p.
    result = result.reshape(len(theta), len(phi), len(theta), 3).transpose(0, 2, 1, 3)
    return result.reshape(len(theta) * len(theta), len(phi), 3)


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
