"""The main job end to end, on real hair.

1. Read the bundled hair file examples/data/bob.hair and summarise it.
2. Generate strands inside the bundled hair mesh examples/data/wavy_cap.hairmesh.json.
3. Build the LoD hierarchy (guides, clusters, elliptical thick hairs) of a real hairstyle made outside
   the project, the bundled examples/data/tressfx/Ratboy_mohawk.tfx (AMD TressFX, MIT license next to
   it), and save it (out/demo/lod: one .hair of thick hairs per level, manifest, arrays).
4. Select levels for a near, a mid and a far camera and report the segments drawn against drawing
   every strand, and what the renderer draws of them with the vertex LoD (strands through the control
   points their shape needs within 0.1 px).
5. Bake the aggregated BCSDF's lookup tables for the asset's hair counts (out/demo/bcsdf, OpenEXR).
6. Judge the LoD's look on converged images (hairlod.quality, as `bench quality` does): at the mid and
   far views, a path-traced full-geometry reference at 1024 spp against full geometry with dual
   scattering and the LoD with the aggregated and with the single-fibre BCSDF, each at 256 spp (the far
   view, whose hair covers fewer pixels, at 8x both: quality.view_spp_scales); print
   segments, seconds, blurred PSNR, the mean hair radiance error per channel and the coverage error,
   and write side-by-side images with the error map (out/demo/images/<view>.png).

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
from hairlod import bcsdf, bcsdf_bake, hair_params, hairmesh, io, lod, quality, render  # noqa: E402
from hairlod.camera import look_at, perspective  # noqa: E402
from hairlod.cli import strand_summary  # noqa: E402

HAIR_FILE = REPO / "examples" / "data" / "bob.hair"
HAIR_MESH = REPO / "examples" / "data" / "wavy_cap.hairmesh.json"
REAL_HAIR = REPO / "examples" / "data" / "tressfx" / "Ratboy_mohawk.tfx"
VIEWPORT = (1280, 720)
OUT = REPO / "out" / "demo"
VIEWS = ("mid", "far")
METHODS = ("pt", "ds", "lod", "lod-single")


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


def real_hair():
    strands = io.read(REAL_HAIR)
    print(f"3. Real hair {REAL_HAIR.name}: {len(strands)} strands, {strands.point_count} points")
    return strands


def build(strands):
    asset, seconds = timed(lod.build_lod, strands)
    hairs = ", ".join(f"L{i}: {len(level.n_total)} ({level.coverage:.1%} covered)"
                      for i, level in enumerate(asset.levels))
    ratios = ", ".join(f"{ratio:.2f}" for ratio in asset.area_ratios)
    print(f"   LoD built in {seconds:.2f} s: {asset.guide_count} guides, {asset.cluster_count} clusters; thick hairs "
          f"{hairs}; cross-section area ratio between levels {ratios or 'n/a'}; "
          f"{asset.memory_bytes / lod.strand_bytes(strands):.2f}x the strands' bytes in memory, "
          f"{asset.stored_bytes / lod.strand_bytes(strands):.2f}x stored")
    return asset


def segments_drawn(selection):
    """Hair segments the selection draws: hairs in each draw range times its segments."""
    draws = np.asarray(selection.draws)
    return int(np.sum(draws[:, 3].astype(np.int64) * draws[:, 5])) if len(draws) else 0


def select_views(asset, strands):
    lower, upper = strands.bounding_box()
    centre, size = (lower + upper) / 2, float(np.linalg.norm(upper - lower))
    projection = perspective(np.radians(40), VIEWPORT[0] / VIEWPORT[1], 0.01 * size, 100 * size)
    full = int(strands.point_count - len(strands))
    print(f"4. Level selection at {VIEWPORT[0]}x{VIEWPORT[1]} px, width threshold 2 px "
          f"(every strand as given: {full} segments):")
    for name, distance in (("near", 1.2), ("mid", 4.0), ("far", 25.0)):
        eye = centre + np.array([0.0, -distance * size, 0.2 * size])
        view = look_at(eye, centre)
        selection, seconds = timed(asset.select, view, projection, VIEWPORT, width_px=2.0)
        drawn = segments_drawn(selection)
        levels = np.bincount(np.asarray(selection.levels).ravel(), minlength=len(asset.levels) + 1)
        camera = {"eye": eye.tolist(), "target": centre.tolist(), "up": [0.0, 0.0, 1.0], "fov_y": np.radians(40),
                  "width": VIEWPORT[0], "height": VIEWPORT[1]}
        strand_geometry, thick = render.lod_geometry(asset, camera, width_px=2.0)
        rendered = ((0 if strand_geometry is None else strand_geometry.point_count - len(strand_geometry)) +
                    (0 if thick is None else len(thick["centres"]) - (len(thick["offsets"]) - 1)))
        print(f"   {name:4s} (distance {distance:>4} x size): {drawn:7d} segments, "
              f"{full / max(drawn, 1):6.1f}x fewer; cluster segments at L0.. / strands {levels.tolist()}; "
              f"skinned and selected in {seconds * 1e3:.1f} ms; with the vertex LoD {rendered} segments, "
              f"{full / max(rendered, 1):.1f}x fewer")


def bake_tables(asset):
    crossed, densest = bcsdf.lod_hair_count_range(asset)
    manifest, seconds = timed(bcsdf_bake.bake, hair_params.as_params(None), OUT / "bcsdf", max_hair_count=crossed)
    size = sum(table["bytes"] for table in manifest["tables"])
    print(f"5. BCSDF tables for n up to {crossed:.1f} (densest cluster: {densest} strands) baked in "
          f"{seconds:.2f} s: {len(manifest['tables'])} tables, {size / 1024:.0f} KB in {(OUT / 'bcsdf').relative_to(REPO)}")


def judge_views(asset, strands):
    result, seconds = timed(quality.bench_quality, strands, asset=asset, views=VIEWS, methods=METHODS, eps_w=(),
                            keep_images=True)
    samples = ", ".join(f"{view} {entry['reference_spp']} / {entry['spp']} spp" for view, entry in result["views"].items())
    print(f"6. Converged images, 128 px, pt reference / each method at {samples} (more where the hair covers fewer "
          "pixels; pt: an independent render, the noise floor, inf where equal to the reference to 8 bits)")
    for view, entry in result["views"].items():
        for method, row in entry["rows"].items():
            blurred = "  inf" if row["blurred_psnr"] is None else f"{row['blurred_psnr']:5.1f}"
            radiance = " / ".join("n/a" if value is None else f"{100 * value:+.1f}" for value in row["radiance_error"])
            coverage = "n/a" if row["coverage_error"] is None else f"{100 * row['coverage_error']:+.1f} %"
            print(f"   {view:4s} {method:10s}: {row['segments']:7d} segments, {row['seconds']:5.2f} s, blurred PSNR "
                  f"{blurred} dB, hair radiance {radiance} % (R / G / B), coverage {coverage}")
    paths = quality.write_view_images(result, result["images"], OUT / "images")
    print(f"   in {seconds:.0f} s; side-by-side images: {', '.join(str(Path(p).relative_to(REPO)) for p in paths)}")


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    summarise_file(HAIR_FILE)
    generate(HAIR_MESH, 20000)
    strands = real_hair()
    asset = build(strands)
    lod.save(asset, OUT / "lod")
    select_views(asset, strands)
    bake_tables(asset)
    judge_views(asset, strands)


if __name__ == "__main__":
    main()
