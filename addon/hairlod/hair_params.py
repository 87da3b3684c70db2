"""Hair fibre parameters: HairParams (the C++ struct), its validation from dicts, and the mapping from
Blender's Principled Hair BSDF (Chiang and Huang modes) and its colour parametrizations."""

import functools
import math

import numpy as np

from . import _core

HairParams = _core.HairParams

FIELDS = ("eta", "sigma_a", "beta_m", "beta_n", "alpha", "coat", "eccentricity", "weight_r", "weight_tt", "weight_trt",
          "fibre", "microfacet_roughness", "aspect_ratio", "huang_sigma_a")
_RGB_FIELDS = ("sigma_a", "huang_sigma_a")
FIBRES = ("chiang", "huang")

# Principled Hair BSDF sockets (snake case) and their Cycles defaults (the Huang sockets: Blender 4.0+).
_PRINCIPLED_DEFAULTS = {
    "model": "CHIANG",
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
    "aspect_ratio": 0.85,
    "reflection": 1.0,
    "transmission": 1.0,
    "secondary_reflection": 1.0,
}
PRINCIPLED_MODELS = ("CHIANG", "HUANG")
# Per-strand noise and the node's mix weight: accepted, not part of a fibre's parameters.
_PRINCIPLED_IGNORED = {"random_color", "random_roughness", "random", "weight"}


def params_to_dict(params):
    """The fields of a HairParams as a plain dict (sigma_a as a list)."""
    params = as_params(params)
    return {name: list(getattr(params, name)) if name in _RGB_FIELDS else getattr(params, name) for name in FIELDS}


def as_params(params=None):
    """A validated HairParams from a HairParams, a dict of its fields, or None (the defaults). A dict
    with ``fibre = "huang"`` that sets none of sigma_a, beta_m, beta_n gets them from the Huang fibre's
    Chiang stand-in (chiang_stand_in), as from_principled_hair gives them."""
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
                setattr(result, name, as_rgb(value, name) if name in _RGB_FIELDS else
                        value if name == "fibre" else float(value))
            except (TypeError, ValueError) as error:
                raise ValueError(f"hair parameter {name} = {value!r}: {error}") from None
        if result.fibre == "huang" and not {"sigma_a", "beta_m", "beta_n"} & set(params):
            result.validate()
            return chiang_stand_in(result)[0]
    else:
        raise ValueError(f"params must be a HairParams or a dict, got {type(params).__name__}")
    result.validate()
    return result


def as_rgb(value, name):
    """3 floats (RGB) from a scalar or 3 values; raises ValueError naming `name` otherwise."""
    array = np.asarray(value, dtype=np.float64).reshape(-1)
    if array.size == 1:
        array = np.repeat(array, 3)
    if array.size != 3:
        raise ValueError(f"{name} needs 1 or 3 values, got {array.size}")
    return [float(v) for v in array]


def from_principled_hair(**node_inputs):
    """HairParams from the inputs of Blender's Principled Hair BSDF.

    Keywords are the node's sockets in snake case (``color``, ``melanin``, ``melanin_redness``, ``tint``,
    ``absorption_coefficient``, ``roughness``, ``radial_roughness``, ``coat``, ``ior``, ``offset`` in
    radians; Blender 4.0+: ``aspect_ratio``, ``reflection``, ``transmission``, ``secondary_reflection``),
    ``parametrization`` ('ABSORPTION', 'MELANIN' or 'COLOR') and ``model`` ('CHIANG', the only model
    before Blender 4.0, or 'HUANG'), the node's enums. Missing inputs take the node's defaults;
    ``random_color``, ``random_roughness``, ``random`` and ``weight`` are ignored. A Huang material gives
    ``fibre = 'huang'`` with its absorption in ``huang_sigma_a`` and sigma_a, beta_m, beta_n of the Chiang
    fibre that stands in for it (chiang_stand_in); matching the albedos takes about 0.1 s and is cached
    per set of inputs.
    """
    unknown = sorted(set(node_inputs) - set(_PRINCIPLED_DEFAULTS) - _PRINCIPLED_IGNORED)
    if unknown:
        raise ValueError(f"unknown Principled Hair input(s) {', '.join(unknown)}")
    if node_inputs.get("model", "CHIANG") not in PRINCIPLED_MODELS:
        raise ValueError(f"model must be one of {', '.join(PRINCIPLED_MODELS)}, got {node_inputs['model']!r}")
    inputs = dict(_PRINCIPLED_DEFAULTS)
    inputs.update({k: v for k, v in node_inputs.items() if k in _PRINCIPLED_DEFAULTS})
    for name in ("color", "tint", "absorption_coefficient"):
        inputs[name] = tuple(as_rgb(inputs[name], name)[:3])
    converted = _converted(tuple(sorted(inputs.items())))
    copy = HairParams()  # the cached object stays unchanged whatever the caller does with its copy
    for name in FIELDS:
        setattr(copy, name, getattr(converted, name))
    return copy


@functools.lru_cache(maxsize=64)
def _converted(items):
    # Cached: a Huang material's stand-in costs ~0.1 s, and the preview asks again on every redraw.
    return _core.params_from_principled_hair(**dict(items))


def chiang_stand_in(params):
    """The Chiang fibre standing in for a Huang fibre (hairlod/bcsdf/chiang_stand_in.h): the same
    roughness, and the absorption that gives the light through its interior the Huang fibre's energy.
    Returns (params with sigma_a, beta_m, beta_n set to the stand-in's, the Huang fibre's albedo, the
    stand-in's albedo), each albedo a dict of RGB arrays 'surface' (R) and 'interior', view-averaged."""
    params, huang, stand_in = _core.chiang_stand_in(as_params(params))
    return params, *({k: np.array(v) for k, v in a.items()} for a in (huang, stand_in))


def sigma_a_from_color(color, beta_n):
    """Chiang et al. 2016, Eq. 9: absorption giving the reflectance colour for roughness beta_n."""
    return np.array(_core.sigma_a_from_color(as_rgb(color, "color"), float(beta_n)))


def sigma_a_from_melanin(eumelanin, pheomelanin=0.0):
    """Absorption of eumelanin and pheomelanin concentrations (Cycles' coefficients)."""
    return np.array(_core.sigma_a_from_melanin(float(eumelanin), float(pheomelanin)))


__all__ = ["FIBRES", "FIELDS", "HairParams", "PRINCIPLED_MODELS", "as_params", "as_rgb", "chiang_stand_in", "from_principled_hair",
           "params_to_dict", "sigma_a_from_color", "sigma_a_from_melanin"]
