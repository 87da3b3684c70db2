"""The main job on the bundled inputs, end to end as far as the pipeline exists today.

1. Read the bundled hair file examples/data/bob.hair and summarise it.
2. Generate strands inside the bundled hair mesh examples/data/wavy_cap.hairmesh.json.
3. Build the LoD hierarchy of the generated hair (guides, clusters, elliptical thick hairs).
4. Select levels for a near, a mid and a far camera and report the segments drawn against drawing
   every strand: the speed side of the LoD (its error side needs the renderer, a later stage).

`make demo` runs this; later stages (bake, preview, render) extend it as they land.
"""

import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "addon"))

import hairlod  # noqa: E402
from hairlod import hairmesh, io, lod  # noqa: E402
from hairlod.camera import look_at, perspective  # noqa: E402
from hairlod.cli import strand_summary  # noqa: E402

HAIR_FILE = REPO / "examples" / "data" / "bob.hair"
HAIR_MESH = REPO / "examples" / "data" / "wavy_cap.hairmesh.json"
VIEWPORT = (1280, 720)


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


def main():
    summarise_file(HAIR_FILE)
    strands = generate(HAIR_MESH, 20000)
    asset = build(strands)
    select_views(asset, strands)


if __name__ == "__main__":
    main()
