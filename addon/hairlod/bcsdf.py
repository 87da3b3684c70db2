"""Hair BCSDFs: single-fibre models, the aggregated BCSDF, white furnace, dual scattering and SRBF
lighting (the fibre parameters: hair_params.py; the baked tables: bcsdf_bake.py).

Directions are in the fibre frame with the tangent along +x (sin(theta) = x), as in pbrt. A value S
follows docs/ARCHITECTURE.md ("BCSDF measure"): L_o = integral of L_i S cos(theta_i) dw_i, so a lossless energy-conserving fibre
has a white furnace of 1. Every function taking parameters accepts a ``HairParams`` or a dict of its
fields (hair_params.as_params).

Models: ``"chiang"`` (d'Eon 2011 / Chiang 2016, as in Cycles; far field, or near field with ``h``),
``"huang"`` (the microfacet fibre of Huang et al. 2022, Blender 4.x's default, as in Cycles; far field;
``huang_sample`` draws directions from it), ``"marschner"`` (Marschner 2003 as in Xu et al. 2011 Sec. 4.1), ``"fiber_rtd"`` (the R, TT, D fibre of
Huang et al. 2025 Eq. 1), ``"realtime"`` (Karis / Tafuri approximations, thesis Sec. 4.3) and
``"aggregated"`` (the thick-hair BCSDF of Huang et al. 2025, Eq. 6-15).
"""

import numpy as np

from . import _core
from .hair_params import as_params, as_rgb

MODELS = ("chiang", "huang", "marschner", "marschner_cg", "fiber_rtd", "realtime", "aggregated")

# Inputs each model takes besides the directions (see evaluate()).
_MODEL_INPUTS = {
    "chiang": {"h"},
    "huang": {"residual_samples"},
    "marschner": {"caustic_width", "caustic_fade_range", "caustic_max_window"},
    "marschner_cg": {"caustic_width", "caustic_fade_range", "caustic_max_window"},
    "fiber_rtd": set(),
    "realtime": {"tt"},
    "aggregated": {"hair_count", "density", "aggregated_fibre"},
}

def cluster_density(hair_total, hair_radius, major_axis, minor_axis):
    """Huang et al. 2025, Sec. 4: area fraction rho of an elliptical cluster covered by its hairs."""
    return _core.cluster_density(float(hair_total), float(hair_radius), float(major_axis), float(minor_axis))


def hairs_crossed(density, ray_length, hair_total, major_axis, minor_axis):
    """Huang et al. 2025, Sec. 4: number n of hairs a ray of length ray_length crosses (at least 1)."""
    return _core.hairs_crossed(float(density), float(ray_length), float(hair_total), float(major_axis),
                               float(minor_axis))


def strands_met(density, ray_length, hair_total, major_axis, minor_axis):
    """The strands a ray meets on average over `ray_length` of in-plane path through a thick hair
    (the Poisson mean the renderer's thick hairs use; Sec. 4's rho), not floored at 1."""
    return _core.expected_hairs_met(float(density), float(ray_length), float(hair_total), float(major_axis),
                                    float(minor_axis))


def lod_hair_count_range(asset):
    """The hair counts a LodAsset's thick hairs need (Huang et al. 2025, Sec. 4 and 5.2): returns
    (max_hairs_crossed, densest_n_total). A ray through a thick hair meets n = rho l sqrt(n_total /
    (pi r_A r_B)) hairs (``hairs_crossed``); at the longest chord l = 2 r_A this is at most
    2 rho sqrt(n_total r_A / (pi r_B)) (rho clamped to 1), and never more than the hair's n_total. Taken over every
    control point of every level, at least 1: the largest n the aggregated tables must cover."""
    crossed, densest = 1.0, 1
    for level in asset.levels:
        if len(level.n_total) == 0:
            continue
        crossed = max(crossed, _core.max_hairs_crossed(level.n_total, level.radii.reshape(-1, 2),
                                                       level.density.reshape(-1)))
        densest = max(densest, int(level.n_total.max()))
    return crossed, densest


def _directions(value, name):
    array = np.ascontiguousarray(value, dtype=np.float32)
    if array.ndim != 2 or array.shape[1] != 3:
        raise ValueError(f"{name} must have shape [N, 3], got {array.shape}")
    return array


def _check_model(model):
    if model not in _MODEL_INPUTS:
        raise ValueError(f"unknown model {model!r}; expected one of {', '.join(MODELS)}")


def evaluate(model, params, wi, wo, **model_inputs):
    """S(wi, wo) for each pair, float32 [N, 3] RGB.

    wi, wo: float [N, 3] in the fibre frame (need not be normalised). Model inputs:
    chiang ``h`` (float [N] offsets in [-1, 1]: near field; default far field, averaged over h);
    marschner ``caustic_width``, ``caustic_fade_range``, ``caustic_max_window``;
    realtime ``tt`` ('tafuri' or 'karis');
    aggregated ``hair_count`` (n >= 1 hairs crossed) and ``density`` (rho in (0, 1]), see cluster_density(),
    and ``aggregated_fibre``, the fibre it widens: 'rtd' (Huang et al. 2025 Eq. 1, the renderer's, default) or
    'material' (the material's Chiang fibre in the far field, the viewport preview's);
    huang ``residual_samples`` (visible normals per width node of its TT / TRT quadrature, default 8).
    """
    _check_model(model)
    unknown = sorted(set(model_inputs) - _MODEL_INPUTS[model])
    if unknown:
        raise ValueError(f"model {model!r} takes no input(s) {', '.join(unknown)}")
    wi = _directions(wi, "wi")
    wo = _directions(wo, "wo")
    if wi.shape != wo.shape:
        raise ValueError(f"wi and wo must have the same shape, got {wi.shape} and {wo.shape}")
    h = model_inputs.pop("h", None)
    if h is not None:
        h = np.ascontiguousarray(h, dtype=np.float32).reshape(-1)
        if h.shape[0] != wi.shape[0]:
            raise ValueError(f"h needs {wi.shape[0]} offsets, got {h.shape[0]}")
    return _core.bcsdf_evaluate(model, as_params(params), wi, wo, h=h, **model_inputs)


def white_furnace(model, params, wo=(0.0, 1.0, 0.0), h=None, tolerance=1e-6, tt="tafuri"):
    """Integral of S(wi, wo) cos(theta_i) dw_i over the sphere (RGB, float64 [3]).

    Adaptive Gauss-Kronrod in double precision; ``h`` selects the chiang near field, ``tt`` the
    realtime model's TT variant ("tafuri" or "karis"). Other models use their default inputs
    (aggregated: n = 1, rho = 1).
    """
    _check_model(model)
    wo = as_rgb(wo, "wo")
    return np.array(_core.bcsdf_white_furnace(model, as_params(params), wo, h=h, tolerance=float(tolerance), tt=tt))


def sphere_kernels(model, params, directions, solid_angles, tangents, views):
    """For each fibre (world-space unit ``tangents`` [M, 3]) seen along ``views`` [M, 3] (unit, towards the
    viewer), S(wi, wo) cos(theta_i) dw_i at radiance samples along ``directions`` [P, 3] (unit, world
    space) of ``solid_angles`` [P]: float64 [M, P, 3]. Summed against radiance [P, 3] over the samples it is
    the fibre's single scattering under that light, by brute force; scripts/bench_world_fit.py holds a
    world's SRBF fit against its image so. A view along the tangent takes any normal-plane azimuth."""
    tangents = np.asarray(tangents, np.float64).reshape(-1, 3)
    views = np.asarray(views, np.float64).reshape(-1, 3)
    directions = np.asarray(directions, np.float64).reshape(-1, 3)
    solid_angles = np.asarray(solid_angles, np.float64).reshape(-1)
    if tangents.shape != views.shape:
        raise ValueError(f"tangents and views must have the same shape, got {tangents.shape} and {views.shape}")
    if solid_angles.shape != (len(directions),):
        raise ValueError(f"solid_angles must have shape [{len(directions)}], got {solid_angles.shape}")
    kernels = np.empty((len(tangents), len(directions), 3))
    for k, (tangent, wo) in enumerate(zip(tangents, views)):
        across = wo - (wo @ tangent) * tangent
        if np.linalg.norm(across) < 1e-9:
            across = np.cross(tangent, [1.0, 0.0, 0.0] if abs(tangent[0]) < 0.9 else [0.0, 1.0, 0.0])
        across /= np.linalg.norm(across)
        frame = np.stack([tangent, across, np.cross(tangent, across)])  # rows: the fibre frame's axes
        wi_local = directions @ frame.T
        fibre = evaluate(model, params, wi_local, np.ascontiguousarray(np.broadcast_to(frame @ wo, wi_local.shape)))
        kernels[k] = fibre * (np.sqrt(np.maximum(1.0 - wi_local[:, 0] ** 2, 0.0)) * solid_angles)[:, None]
    return kernels


def huang_sample(params, wo, u):
    """Directions drawn from the Huang fibre for the views wo (float [N, 3], fibre frame) with uniforms u
    (float [N, 11] in [0, 1)): (wi [N, 3], weight [N, 3] = S cos(theta_i) / pdf, 0 where no path leaves;
    discarded [N, 3], the throughput the model's visibility rules drop on the path: light arriving where
    the tilted cuticle faces away from wo, paths a cuticle sends into the fibre's own surface).
    As in Cycles, the model has no density to evaluate: a sample carries its weight. A lossless fibre's
    energy is the mean weight, and weight + discarded averages to 1 (within 1e-3)."""
    wo = np.ascontiguousarray(wo, dtype=np.float64)
    u = np.ascontiguousarray(u, dtype=np.float64)
    if wo.ndim != 2 or wo.shape[1] != 3:
        raise ValueError(f"wo must have shape [N, 3], got {wo.shape}")
    if u.shape != (wo.shape[0], 11):
        raise ValueError(f"u must have shape [{wo.shape[0]}, 11], got {u.shape}")
    return _core.huang_sample(as_params(params), wo, u)


def dual_scattering(params, theta_d, model="chiang", backscatter_density=_core.DEFAULT_BACKSCATTER_DENSITY, tolerance=1e-6):
    """Zinke et al. 2008 dual-scattering terms of the fibre, tabulated over theta_d (radians).

    Returns a dict: ``theta_d`` [K] and, each [K, 3] RGB, ``a_f``, ``a_b`` (average forward/backward
    attenuation), ``alpha_f``, ``alpha_b`` (shifts), ``beta_f``, ``beta_b`` (widths), ``A_1``, ``A_3``,
    ``A_b``, ``delta_b``, ``sigma_b``.
    """
    _check_model(model)
    theta_d = np.ascontiguousarray(np.atleast_1d(theta_d), dtype=np.float64)
    return _core.bcsdf_dual_scattering(model, as_params(params), theta_d, backscatter_density=float(backscatter_density),
                                       tolerance=float(tolerance))


def _srbf_inputs(caller, lights, wo, marschner_inputs):
    """(directions, lambdas, coefficients, wo) as contiguous float64 arrays, checked for `caller`."""
    unknown = sorted(set(marschner_inputs) - _MODEL_INPUTS["marschner"])
    if unknown:
        raise ValueError(f"{caller} takes no input(s) {', '.join(unknown)}")
    for key in ("directions", "lambdas", "coefficients"):
        if key not in lights:
            raise ValueError(f"lights needs {key!r}")
    wo = np.ascontiguousarray(wo, dtype=np.float64)
    if wo.ndim != 2 or wo.shape[1] != 3:
        raise ValueError(f"wo must have shape [M, 3], got {wo.shape}")
    return (*(np.ascontiguousarray(lights[key], dtype=np.float64) for key in ("directions", "lambdas", "coefficients")),
            wo)


def srbf_single_scattering(params, lights, wo, m=4, **marschner_inputs):
    """Single scattering of the Marschner fibre under SRBF lights (Xu et al. 2011, Eq. 2 and 11-14):
    for each view direction, sum_j L_j * integral of G_j(wi) S(wi, wo) cos(theta_i) dw_i, float64 [M, 3].

    ``lights``: a dict of SRBF lights (``directions`` [N, 3], ``lambdas`` [N],
    ``coefficients`` [N, 3]), with directions in the fibre frame like ``wo`` [M, 3]; ``m`` is the
    linear quadrature's order (Sec. 4.2.2); marschner inputs as in evaluate().
    """
    directions, lambdas, coefficients, wo = _srbf_inputs("srbf_single_scattering", lights, wo, marschner_inputs)
    return _core.bcsdf_srbf_single_scattering(as_params(params), directions, lambdas, coefficients, wo, m=int(m),
                                              **marschner_inputs)


def srbf_multiple_scattering(params, lights, wo, forward_attenuation=1.0, forward_variance=0.0,
                             forward_density=_core.DEFAULT_FORWARD_DENSITY,
                             backscatter_density=_core.DEFAULT_BACKSCATTER_DENSITY, m=4, table_samples=33,
                             components=False, reference=False, theta_samples=256, phi_samples=512,
                             **marschner_inputs):
    """Multiple scattering of the Marschner fibre under SRBF lights with dual scattering
    (Xu et al. 2011, Eq. 3-5 and Sec. 4.3, Eq. 27-31; Zinke et al. 2008): for each view direction,
    sum_j d_f T_f,j L_j * integral of L_f,j(wi) (S + d_b S_back)(wi, wo) cos(theta_i) dw_i, float64 [M, 3].

    ``lights`` as in srbf_single_scattering. The forward-scattering state of each light's shadow path:
    ``forward_attenuation`` T_f in [0, 1] (scalar, RGB [3] or per light [N, 3]) and ``forward_variance``
    sigma_f-bar^2 >= 0 in rad^2 (scalar or per light [N]); ``forward_density`` d_f and
    ``backscatter_density`` d_b in [0, 1]; ``table_samples`` theta_d nodes of the A_b, Delta_b,
    sigma_b table. ``components=True`` returns (global, local) instead of their sum;
    ``reference=True`` integrates the same model by brute force on a theta x phi grid.
    """
    directions, lambdas, coefficients, wo = _srbf_inputs("srbf_multiple_scattering", lights, wo, marschner_inputs)
    count = len(directions)
    attenuation = np.asarray(forward_attenuation, dtype=np.float64)
    if attenuation.ndim == 0 or attenuation.shape == (3,):
        attenuation = np.broadcast_to(attenuation, (count, 3))
    if attenuation.shape != (count, 3):
        raise ValueError(f"forward_attenuation must be a scalar, [3] or [{count}, 3], got {attenuation.shape}")
    variance = np.asarray(forward_variance, dtype=np.float64)
    if variance.ndim == 0:
        variance = np.broadcast_to(variance, (count,))
    if variance.shape != (count,):
        raise ValueError(f"forward_variance must be a scalar or [{count}], got {variance.shape}")
    global_part, local_part = _core.bcsdf_srbf_multiple_scattering(
        as_params(params), directions, lambdas, coefficients, wo, np.ascontiguousarray(attenuation),
        np.ascontiguousarray(variance), forward_density=float(forward_density),
        backscatter_density=float(backscatter_density), table_samples=int(table_samples), m=int(m),
        reference=bool(reference), theta_samples=int(theta_samples), phi_samples=int(phi_samples),
        **marschner_inputs)
    return (global_part, local_part) if components else global_part + local_part


__all__ = [
    "MODELS",
    "huang_sample",
    "cluster_density",
    "hairs_crossed",
    "strands_met",
    "lod_hair_count_range",
    "dual_scattering",
    "evaluate",
    "srbf_multiple_scattering",
    "srbf_single_scattering",
    "white_furnace",
]
