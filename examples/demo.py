"""The main job on the bundled inputs, end to end.

1. Read the bundled hair file examples/data/bob.hair and summarise it.
2. Generate strands inside the bundled hair mesh examples/data/wavy_cap.hairmesh.json.
3. Build the LoD hierarchy of the generated hair (guides, clusters, elliptical thick hairs) and save
   it (out/demo/lod: one .hair of thick hairs per level, manifest, arrays).
4. Select levels for a near, a mid and a far camera and report the segments drawn against drawing
   every strand.
5. Bake the aggregated BCSDF's lookup tables for the asset's hair counts (out/demo/bcsdf, OpenEXR).
6. Render preview images with the Embree renderer (out/demo/*.png) at the mid and far views: the
   LoD with the aggregated BCSDF, and full geometry at the same samples per pixel, against a
   full-geometry path-traced reference at more samples; print the speed-against-error summary
   (segments, seconds, PSNR and FLIP).

`make demo` runs this. The viewport preview of the same asset needs a Blender window: see the
README (LoD Preview) and scripts/bench_lod_preview.py.
"""

import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "addon"))

import hairlod  # noqa: E402
from hairlod import bcsdf, flip, hairmesh, io, lod, render  # noqa: E402
from hairlod.camera import look_at, perspective  # noqa: E402
from hairlod.cli import strand_summary  # noqa: E402

HAIR_FILE = REPO / "examples" / "data" / "bob.hair"
HAIR_MESH = REPO / "examples" / "data" / "wavy_cap.hairmesh.json"
VIEWPORT = (1280, 720)
OUT = REPO / "out" / "demo"
RENDER_WIDTH = 200
RENDER_SPP = 16
REFERENCE_SPP = 96


def timed(function, *args, **kwargs):
    start = time.perf_counter()
    result = function(*args, **kwargs)
    return result, time.perf_counter() - start


def summarise_file(path):
    strands, seconds = timed(io.read, path)
    summary = strand_summary(strands)
    per_strand = summary["points_per_strand"]
    print(f"1. {path.relative_to(REPO)}: {summary['strands']} strands, {summary['points']} points "
          f"({per_strand['min']}-{per_strand['max']} per strand), read in {seconds * 1e3:.1f} ms")


def generate(path, count):
    source = hairmesh.read(path)
    strands, seconds = timed(hairlod.generate_strands, source, count=count, vertices=17, seed=1)
    print(f"2. {path.relative_to(REPO)}: {source.mesh.face_count} bundles -> {len(strands)} strands of "
          f"{strands.point_count // len(strands)} points in {seconds:.3f} s")
    return strands


def build(strands):
    asset, seconds = timed(lod.build_lod, strands, guides=128, levels=6, control_points=16, seed=0)
    hairs = ", ".join(f"L{i}: {len(level.n_total)} ({level.coverage:.1%} covered)"
                      for i, level in enumerate(asset.levels))
    ratios = ", ".join(f"{ratio:.2f}" for ratio in asset.area_ratios)
    print(f"3. LoD built in {seconds:.2f} s: {asset.cluster_count} clusters; thick hairs {hairs}; "
          f"cross-section area ratio between levels {ratios or 'n/a'}")
    return asset


def segments_drawn(selection):
    """Hair segments the selection draws: hairs in each draw range times its segments."""
    draws = np.asarray(selection.draws)
    return int(np.sum(draws[:, 3].astype(np.int64) * draws[:, 5])) if len(draws) else 0


def select_views(asset, strands):
    lower, upper = strands.bounding_box()
    centre, size = (lower + upper) / 2, float(np.linalg.norm(upper - lower))
    projection = perspective(np.radians(40), VIEWPORT[0] / VIEWPORT[1], 0.01 * size, 100 * size)
    full = len(strands) * (asset.control_points - 1)
    print(f"4. Level selection at {VIEWPORT[0]}x{VIEWPORT[1]} px, width threshold 2 px "
          f"(all strands: {full} segments):")
    for name, distance in (("near", 1.2), ("mid", 4.0), ("far", 25.0)):
        view = look_at(centre + np.array([0.0, -distance * size, 0.2 * size]), centre)
        selection, seconds = timed(asset.select, view, projection, VIEWPORT, width_px=2.0)
        drawn = segments_drawn(selection)
        levels = np.bincount(np.asarray(selection.levels).ravel(), minlength=len(asset.levels) + 1)
        print(f"   {name:4s} (distance {distance:>4} x size): {drawn:7d} segments, "
              f"{full / max(drawn, 1):6.1f}x fewer; cluster segments at L0.. / strands {levels.tolist()}; "
              f"skinned and selected in {seconds * 1e3:.1f} ms")


def bake_tables(asset):
    crossed, densest = bcsdf.lod_hair_count_range(asset)
    manifest, seconds = timed(bcsdf.bake, bcsdf.as_params(None), OUT / "bcsdf", max_hair_count=crossed)
    size = sum(table["bytes"] for table in manifest["tables"])
    print(f"5. BCSDF tables for n up to {crossed:.1f} (densest cluster: {densest} strands) baked in "
          f"{seconds:.2f} s: {len(manifest['tables'])} tables, {size / 1024:.0f} KB in {(OUT / 'bcsdf').relative_to(REPO)}")


def render_views(asset, strands):
    print(f"6. Embree renders, {RENDER_WIDTH} px wide, {RENDER_SPP} spp (reference: path-traced full geometry, "
          f"{REFERENCE_SPP} spp):")
    for view in ("mid", "far"):
        reference = render.render(strands, "pt", view, width=RENDER_WIDTH, spp=REFERENCE_SPP, seed=7)
        render.write_image(str(OUT / f"{view}_reference.png"), reference["image"])
        for method, label in (("pt", "full geometry"), ("lod", "LoD, aggregated BCSDF")):
            result = render.render(strands, method, view, width=RENDER_WIDTH, spp=RENDER_SPP, asset=asset, seed=1)
            render.write_image(str(OUT / f"{view}_{method}.png"), result["image"])
            error = flip.flip(render.to_srgb8(result["image"]) / 255.0, render.to_srgb8(reference["image"]) / 255.0)
            print(f"   {view:4s} {label:22s}: {result['segments']:7d} segments, {result['seconds']:6.2f} s, "
                  f"PSNR {render.psnr(result['image'], reference['image']):5.1f} dB, FLIP {error:.3f}")
    print(f"   images in {OUT.relative_to(REPO)}")


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    summarise_file(HAIR_FILE)
    strands = generate(HAIR_MESH, 20000)
    asset = build(strands)
    lod.save(asset, OUT / "lod")
    select_views(asset, strands)
    bake_tables(asset)
    render_views(asset, strands)


if __name__ == "__main__":
    main()
