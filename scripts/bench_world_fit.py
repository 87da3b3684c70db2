"""Measures how well the preview's SRBF fit of a world stands for the world as the hair sees it, and what
the fit costs, against the fit of earlier releases (fixed Fibonacci centres, the bandwidth their spacing).

Run: blender -b --factory-startup --python scripts/bench_world_fit.py [-- --worlds city,courtyard --pairs 300 --out F.json]
For each of Blender's studio-light worlds (datafiles/studiolights/world, read through bpy as the preview
reads them) or the .exr / .hdr paths given: the samples the preview fits (hairlod.world_lighting.
equirectangular_samples: its sun taken out, 32 rows), and the Chiang fibre's single scattering under
them, integrated by brute force over the samples (sum of S(wi, wo) cos(theta_i) L(wi) dw_i,
hairlod.bcsdf.evaluate), for --pairs random (tangent, view) pairs of a fixed seed. Each fit's error is
the RMS over the pairs of the luminance of its response minus the image's, over the RMS of the image's;
its mean is the mean response over the image's. Also its bandwidth, its relative error over the samples,
and its time (median of --runs fits). Prints a table and writes --out as JSON.
"""

import argparse
import glob
import json
import os
import sys
import time

import bpy
import numpy as np

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
from hairlod import bcsdf, world_lighting  # noqa: E402
from hairlod.blender.preview.world_srbf import image_radiance  # noqa: E402

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
FITS = (("fibonacci", False), ("light", True))  # (name, fit_world's adaptive)


def parse_args():
    parser = argparse.ArgumentParser()
    parser.add_argument("--worlds", help="comma-separated studio-light world names or image paths (default: every "
                                         "studio-light world)")
    parser.add_argument("--pairs", type=int, default=300)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--out")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def studio_worlds():
    folder = bpy.utils.system_resource('DATAFILES', path=os.path.join("studiolights", "world"))
    return {os.path.splitext(os.path.basename(path))[0]: path for path in sorted(glob.glob(os.path.join(folder, "*.exr")))}


def main():
    args = parse_args()
    if args.pairs < 1 or args.runs < 1:
        raise SystemExit("--pairs and --runs must be >= 1")
    known = studio_worlds()
    names = args.worlds.split(",") if args.worlds else sorted(known)
    rng = np.random.default_rng(3)
    tangents, views = (v / np.linalg.norm(v, axis=1, keepdims=True) for v in rng.normal(size=(2, args.pairs, 3)))
    results = {}
    kernels = None
    for name in names:
        path = known.get(name, name)
        if not os.path.isfile(path):
            raise SystemExit(f"--worlds: no studio-light world or file {name!r} (Blender has: {', '.join(known)})")
        image = bpy.data.images.load(path, check_existing=True)
        directions, solid_angles, radiance, sun, _ = world_lighting.equirectangular_samples(image_radiance(image))
        if kernels is None or kernels.shape[1] != len(directions):
            kernels = bcsdf.sphere_kernels("chiang", None, directions, solid_angles, tangents, views)
        truth = np.einsum("pnc,nc->pc", kernels, radiance) @ LUMINANCE
        entry = {"sun": sun is not None}
        for fit_name, adaptive in FITS:
            seconds = []
            for _ in range(args.runs):
                start = time.perf_counter()
                lights = world_lighting.fit_world(directions, solid_angles, radiance, adaptive=adaptive)
                seconds.append(time.perf_counter() - start)
            response = np.einsum("pnc,nc->pc", kernels, world_lighting.world_radiance(lights, directions)) @ LUMINANCE
            entry[fit_name] = {"response_error": float(np.sqrt(np.mean((response - truth) ** 2) / np.mean(truth ** 2))),
                               "response_mean": float(response.mean() / truth.mean()), "bandwidth": lights.lam,
                               "relative_error": lights.relative_error, "seconds": float(np.median(seconds))}
        results[name] = entry
        print(f"{name:10s} " + " | ".join(
            f"{fit_name}: response error {entry[fit_name]['response_error']:.3f}, mean {entry[fit_name]['response_mean']:.3f}, "
            f"bandwidth {entry[fit_name]['bandwidth']:.2f}, fit error {entry[fit_name]['relative_error']:.2f}, "
            f"{1000.0 * entry[fit_name]['seconds']:.1f} ms" for fit_name, _ in FITS), flush=True)
    if args.out:
        with open(args.out, "w") as out:
            json.dump(results, out, indent=1)


main()
