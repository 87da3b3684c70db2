"""The aggregated BCSDF baked into lookup tables: bake() writes one float32 OpenEXR per table and a
manifest into a folder that appears complete or not at all; lut_lookup() reads such a table."""

import numpy as np

from . import _core
from .hair_params import as_params, params_to_dict

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


__all__ = ["BAKE_FORMAT", "BAKE_WHAT", "DEFAULT_TABLE_SAMPLES", "bake", "bake_bytes", "lut_lookup"]
