"""Hair BCSDFs: fibre parameters, single-fibre models, white furnace and dual scattering.

Directions are in the fibre frame with the tangent along +x (sin(theta) = x), as in pbrt. A value S
follows docs/ARCHITECTURE.md ("BCSDF measure"): L_o = integral of L_i S cos(theta_i) dw_i, so a lossless energy-conserving fibre
has a white furnace of 1. Every function taking parameters accepts a ``HairParams`` or a dict of its
fields.

Models: ``"chiang"`` (d'Eon 2011 / Chiang 2016, as in Cycles; far field, or near field with ``h``),
``"marschner"`` (Marschner 2003 as in Xu et al. 2011 Sec. 4.1), ``"fiber_rtd"`` (the R, TT, D fibre of
Huang et al. 2025 Eq. 1), ``"realtime"`` (Karis / Tafuri approximations, thesis Sec. 4.3) and
``"aggregated"`` (the thick-hair BCSDF of Huang et al. 2025, Eq. 6-15).
"""

import math

import numpy as np

from . import _core

HairParams = _core.HairParams

FIELDS = ("eta", "sigma_a", "beta_m", "beta_n", "alpha", "coat", "eccentricity", "weight_r", "weight_tt", "weight_trt")
MODELS = ("chiang", "marschner", "marschner_cg", "fiber_rtd", "realtime", "aggregated")

# Inputs each model takes besides the directions (see evaluate()).
_MODEL_INPUTS = {
    "chiang": {"h"},
    "marschner": {"caustic_width", "caustic_fade_range", "caustic_max_window"},
    "marschner_cg": {"caustic_width", "caustic_fade_range", "caustic_max_window"},
    "fiber_rtd": set(),
    "realtime": {"tt"},
    "aggregated": {"hair_count", "density"},
}

# Principled Hair BSDF sockets (snake case) and their Cycles 3.4 defaults.
_PRINCIPLED_DEFAULTS = {
    "parametrization": "COLOR",
    "color": (0.017513, 0.005763, 0.002059),
    "melanin": 0.8,
    "melanin_redness": 1.0,
    "tint": (1.0, 1.0, 1.0),
    "absorption_coefficient": (0.245531, 0.52, 1.365),
    "roughness": 0.3,
    "radial_roughness": 0.3,
    "coat": 0.0,
    "ior": 1.55,
    "offset": math.radians(2.0),
}
# Per-strand noise and the node's model switch: accepted, not part of a fibre's parameters.
_PRINCIPLED_IGNORED = {"random_color", "random_roughness", "random", "model"}


def params_to_dict(params):
    """The fields of a HairParams as a plain dict (sigma_a as a list)."""
    params = as_params(params)
    return {name: list(params.sigma_a) if name == "sigma_a" else getattr(params, name) for name in FIELDS}


def as_params(params=None):
    """A validated HairParams from a HairParams, a dict of its fields, or None (the defaults)."""
    if params is None:
        result = HairParams()
    elif isinstance(params, HairParams):
        result = params
    elif isinstance(params, dict):
        unknown = sorted(set(params) - set(FIELDS))
        if unknown:
            raise ValueError(f"unknown hair parameter(s) {', '.join(unknown)}; expected {', '.join(FIELDS)}")
        result = HairParams()
        for name, value in params.items():
            try:
                setattr(result, name, _rgb(value, name) if name == "sigma_a" else float(value))
            except (TypeError, ValueError) as error:
                raise ValueError(f"hair parameter {name} = {value!r}: {error}") from None
    else:
        raise ValueError(f"params must be a HairParams or a dict, got {type(params).__name__}")
    result.validate()
    return result


def _rgb(value, name):
    array = np.asarray(value, dtype=np.float64).reshape(-1)
    if array.size == 1:
        array = np.repeat(array, 3)
    if array.size != 3:
        raise ValueError(f"{name} needs 1 or 3 values, got {array.size}")
    return [float(v) for v in array]


def from_principled_hair(**node_inputs):
    """HairParams from the inputs of Blender's Principled Hair BSDF (Cycles 3.4, Chiang model).

    Keywords are the node's sockets in snake case (``color``, ``melanin``, ``melanin_redness``, ``tint``,
    ``absorption_coefficient``, ``roughness``, ``radial_roughness``, ``coat``, ``ior``, ``offset`` in
    radians) and ``parametrization`` ('ABSORPTION', 'MELANIN' or 'COLOR', the node's enum). Missing
    inputs take the node's defaults; ``random_color``, ``random_roughness`` and ``random`` are ignored.
    """
    unknown = sorted(set(node_inputs) - set(_PRINCIPLED_DEFAULTS) - _PRINCIPLED_IGNORED)
    if unknown:
        raise ValueError(f"unknown Principled Hair input(s) {', '.join(unknown)}")
    if node_inputs.get("model", "CHIANG") != "CHIANG":
        raise ValueError(f"model must be 'CHIANG' (the Cycles 3.4 model), got {node_inputs['model']!r}")
    inputs = dict(_PRINCIPLED_DEFAULTS)
    inputs.update({k: v for k, v in node_inputs.items() if k in _PRINCIPLED_DEFAULTS})
    for name in ("color", "tint", "absorption_coefficient"):
        inputs[name] = _rgb(inputs[name], name)[:3]
    return _core.params_from_principled_hair(**inputs)


def sigma_a_from_color(color, beta_n):
    """Chiang et al. 2016, Eq. 9: absorption giving the reflectance colour for roughness beta_n."""
    return np.array(_core.sigma_a_from_color(_rgb(color, "color"), float(beta_n)))


def sigma_a_from_melanin(eumelanin, pheomelanin=0.0):
    """Absorption of eumelanin and pheomelanin concentrations (Cycles' coefficients)."""
    return np.array(_core.sigma_a_from_melanin(float(eumelanin), float(pheomelanin)))


def cluster_density(hair_total, hair_radius, major_axis, minor_axis):
    """Huang et al. 2025, Sec. 4: area fraction rho of an elliptical cluster covered by its hairs."""
    return _core.cluster_density(float(hair_total), float(hair_radius), float(major_axis), float(minor_axis))


def hairs_crossed(density, ray_length, hair_total, major_axis, minor_axis):
    """Huang et al. 2025, Sec. 4: number n of hairs a ray of length ray_length crosses (at least 1)."""
    return _core.hairs_crossed(float(density), float(ray_length), float(hair_total), float(major_axis),
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
    aggregated ``hair_count`` (n >= 1 hairs crossed) and ``density`` (rho in (0, 1]), see cluster_density().
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
    wo = _rgb(wo, "wo")
    return np.array(_core.bcsdf_white_furnace(model, as_params(params), wo, h=h, tolerance=float(tolerance), tt=tt))


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


# theta_d nodes of the per-hair table the aggregated tables interpolate: the default set bakes in
# about 0.5 s on 2 cores (129: 1.1 s); see bench bcsdf for the error against it.
DEFAULT_TABLE_SAMPLES = 65


def bake_bytes(theta_samples, hair_count_samples, table_samples, tables=("aggregated",)):
    """Bytes bake() holds at its peak (tables as doubles in C++, float32 copies, EXR buffers), for
    the memory budget."""
    theta, count, per_hair = (max(int(v), 0) for v in (theta_samples, hair_count_samples, table_samples))
    aggregated = (30 * theta + 9 * theta * count) * (8 + 4 + 4) + per_hair * 512 if "aggregated" in tables else 0
    return aggregated + (64 << 20 if "xu" in tables else 0)


BAKE_FORMAT = "hairlod-bcsdf-lut"  # the manifest "format" that marks a folder as tables hairlod baked
BAKE_WHAT = "a BCSDF table folder"  # the kind in messages


def bake(params, out_dir, theta_samples=64, hair_count_samples=64, max_hair_count=64.0,
         table_samples=DEFAULT_TABLE_SAMPLES,
         tables=("aggregated",), force=False, inputs=()):
    """Bake lookup tables into ``out_dir``: one float32 OpenEXR per table and manifest.json.
    ``tables`` names the sets: "aggregated" (the aggregated BCSDF's attenuation and dual-scattering
    tables, sampled from a per-hair table of ``table_samples`` theta_d nodes) and "xu" (Xu et al.
    2011's C_k, H_k^TT, H_k^TRT, global, about 0.3 s). The folder appears complete or not at all
    (atomic_output.replace_folder); an existing folder is replaced only when it holds tables hairlod
    baked, or with ``force``, and never when it holds one of ``inputs`` (paths this run reads, such
    as the LoD folder the hair-count range came from). Returns the manifest (a dict).

    Manifest: {"format": "hairlod-bcsdf-lut", "version": 1, "model": "aggregated", "params": {...},
    "tables": [{"name", "file", "equation", "axes": [{"name", "range": [lo, hi], "samples",
    "image_axis": "x" | "y", "scale": "log" only when nodes are log-uniform}], "resolution": [width, height], "channels": [...], "bytes"}]}. Texel
    centres sit on the axis nodes (node k at lo + (hi - lo) k / (samples - 1)); look up with linear
    interpolation after mapping the coordinate to (k + 0.5) / samples. EXR files store channels sorted
    by name: read them by name.
    """
    import os

    from . import atomic_output, memory_budget, strict_json

    params = as_params(params)
    if isinstance(tables, str):
        tables = [tables]
    tables = list(tables)
    memory_budget.check(bake_bytes(theta_samples, hair_count_samples, table_samples, tables),
                        f"baking {', '.join(tables)} tables of {theta_samples} x {hair_count_samples} samples, "
                        f"per-hair table {table_samples} (theta_samples, hair_count_samples, table_samples)")
    # Refused before the bake runs, so a refusal costs nothing.
    atomic_output.check_folder_target(os.path.abspath(os.fspath(out_dir)), BAKE_FORMAT, force, inputs, BAKE_WHAT)
    baked = _core.bcsdf_bake(params, theta_samples=int(theta_samples), hair_count_samples=int(hair_count_samples),
                             max_hair_count=float(max_hair_count), table_samples=int(table_samples), tables=tables)

    def write(folder):
        manifest = {"format": BAKE_FORMAT, "version": 1, "model": "aggregated", "params": params_to_dict(params),
                    "tables": []}
        for table in baked:
            file_name = table["name"] + ".exr"
            values = table["values"]
            _core.write_exr(os.path.join(folder, file_name), values, table["channels"])
            axes = [{"name": axis["name"], "range": list(axis["range"]), "samples": axis["samples"],
                     "image_axis": "xy"[k], **({"scale": axis["scale"]} if "scale" in axis else {})}
                    for k, axis in enumerate(table["axes"])]
            manifest["tables"].append({"name": table["name"], "file": file_name, "equation": table["equation"],
                                       "axes": axes, "resolution": [values.shape[1], values.shape[0]],
                                       "channels": list(table["channels"]), "bytes": int(values.nbytes)})
        text = strict_json.dumps(manifest, indent=2)
        with open(os.path.join(folder, "manifest.json"), "w") as f:
            f.write(text)
        return manifest

    return atomic_output.replace_folder(out_dir, BAKE_FORMAT, write, force=force, inputs=inputs, what=BAKE_WHAT)


def lut_lookup(values, axes, coordinates):
    """Linear (1D) or bilinear (2D) lookup of a baked table ``values`` [H, W, C] whose ``axes`` are the
    manifest's; ``coordinates`` [K, len(axes)] in axis units, clamped to the ranges (log-scaled axes are
    interpolated in log(value)). Returns [K, C]."""
    values = np.asarray(values, dtype=np.float64)
    coordinates = np.atleast_2d(np.asarray(coordinates, dtype=np.float64))
    positions = []
    for k, axis in enumerate(axes):
        lo, hi = axis["range"]
        c = coordinates[:, k]
        if axis.get("scale") == "log":
            lo, hi, c = np.log(lo), np.log(hi), np.log(np.maximum(c, 1e-300))
        x = np.clip((c - lo) / (hi - lo), 0.0, 1.0) * (axis["samples"] - 1)
        i = np.minimum(x.astype(np.int64), axis["samples"] - 2)
        positions.append((i, (x - i)[:, None]))
    (ix, tx) = positions[0]
    (iy, ty) = positions[1] if len(axes) > 1 else (np.zeros_like(ix), np.zeros_like(tx))
    iy1 = np.minimum(iy + 1, values.shape[0] - 1)
    return ((1 - ty) * ((1 - tx) * values[iy, ix] + tx * values[iy, ix + 1]) +
            ty * ((1 - tx) * values[iy1, ix] + tx * values[iy1, ix + 1]))


__all__ = [
    "BAKE_FORMAT",
    "DEFAULT_TABLE_SAMPLES",
    "FIELDS",
    "MODELS",
    "HairParams",
    "as_params",
    "bake",
    "bake_bytes",
    "cluster_density",
    "hairs_crossed",
    "lod_hair_count_range",
    "lut_lookup",
    "dual_scattering",
    "evaluate",
    "from_principled_hair",
    "params_to_dict",
    "sigma_a_from_color",
    "sigma_a_from_melanin",
    "srbf_multiple_scattering",
    "srbf_single_scattering",
    "white_furnace",
]
