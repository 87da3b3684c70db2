"""Benchmarks the viewport LoD preview in a real Blender window (run under Xvfb).

Run: xvfb-run -a -s '-screen 0 1280x720x24' blender --factory-startup --python scripts/bench_lod_preview.py
     [-- --count 100000 --frames 24 --guides 256 --rounds R --shadowing S --out FILE.json]
Generates --count strands in examples/data/wavy_cap.hairmesh.json, builds their LoD (--guides guides, 6
levels) and previews it on an empty, lit by a sun (--shadowing: the panel's Shadowing, else its default;
0 turns the self-shadowing and the opacity maps off). A camera dolly from 0.7x to 30x the hair's size
over --frames frames (one redraw per frame) is captured twice: with the LoD at
eps_w = 2 px (and the default vertex LoD) and with every strand at every control point. Prints one JSON object: per frame the segments drawn, the
selection + selection-texture upload time (in each of --rounds dollies; their median and maximum over
every frame but the first), the PSNR of the LoD frame against the all-strand frame, and the
adjacent-frame PSNR of both (over the hair's bounding box) (the paper's Fig. 9 measure of popping); and the draw time of a frame at
the far view without hair, with the LoD and with every strand (wm.redraw_timer, 10 redraws).
"""

import argparse
import os
import sys
import time

import bpy
import numpy as np

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import window_steps  # noqa: E402  (scripts/window_steps.py)
from viewport_capture import add_sun, bare_viewport, capture, psnr, redraw  # noqa: E402  (scripts/viewport_capture.py)

sys.path.insert(0, os.path.join(REPO_ROOT, "tests", "blender"))

HAIR_MESH = os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json")


def parse_args():
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=100000)
    parser.add_argument("--frames", type=int, default=24)
    parser.add_argument("--guides", type=int, default=256)
    parser.add_argument("--rounds", type=int, default=1,
                        help="dollies with the LoD whose selection times count (the first is also captured)")
    parser.add_argument("--shadowing", type=float, help="the panel's Shadowing (default: the panel's default)")
    parser.add_argument("--out")
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def run(args):
    import addon_utils

    addon_utils.enable("hairlod", default_set=True)
    import hairlod
    from hairlod import hairmesh, lod
    from hair_fixtures import preview_on_an_empty  # tests/blender/hair_fixtures.py

    strands = hairlod.generate_strands(hairmesh.read(HAIR_MESH), count=args.count, vertices=17, seed=1)
    start = time.perf_counter()
    asset = lod.build_lod(strands, guides=args.guides, levels=6, control_points=16, seed=0)
    build_seconds = time.perf_counter() - start
    lower, upper = strands.points.min(axis=0), strands.points.max(axis=0)
    centre, size = 0.5 * (lower + upper), float(np.linalg.norm(upper - lower))

    _, settings, preview = preview_on_an_empty(asset)
    if args.shadowing is not None:
        settings.self_shadowing = args.shadowing
    add_sun(bpy.context.scene)

    window, area, region, region_3d = bare_viewport(size)
    region_3d.view_location = centre
    region_3d.view_rotation = (0.8, 0.45, 0.2, 0.35)
    region_3d.view_rotation.normalize()
    out_dir = os.environ.get("TMPDIR", "/tmp")
    distances = np.geomspace(0.7, 30.0, args.frames) * size

    def dolly(width_px):
        settings.width_px = width_px
        # Every strand means every control point too (the strands' vertex LoD off), as Blender draws them.
        settings.vertex_tolerance_px = default_tolerance if width_px >= 1.0 else 0.0
        preview.views.clear()
        frames = []
        for k, distance in enumerate(distances):
            region_3d.view_distance = float(distance)
            redraw(window, area, region)
            stats = dict(preview.stats)
            frames.append((capture(window, area, os.path.join(out_dir, f"dolly_{k}.png")), stats))
        return frames

    default_tolerance = settings.vertex_tolerance_px
    settings.enabled = False
    redraw(window, area, region)
    background = capture(window, area, os.path.join(out_dir, "dolly_background.png"))
    settings.enabled = True
    with_lod = dolly(2.0)
    # More dollies with the LoD, not captured, for more samples of the selection time per frame (each
    # starts from a new view, so that every frame changes the selection as in the first).
    select_rounds = [[stats["select_ms"] for _, stats in with_lod]]
    for _ in range(args.rounds - 1):
        preview.views.clear()
        select_rounds.append([])
        for distance in distances:
            region_3d.view_distance = float(distance)
            redraw(window, area, region)
            select_rounds[-1].append(preview.stats["select_ms"])
    with_strands = dolly(1e-3)
    frames = []
    for k in range(args.frames):
        image, stats = with_lod[k]
        reference = with_strands[k][0]
        frame = {"distance_over_size": float(distances[k] / size), "segments": stats["segments"],
                 "segments_all_strands": with_strands[k][1]["segments"],
                 "select_ms": stats["select_ms"], "select_ms_rounds": [times[k] for times in select_rounds],
                 "psnr_vs_strands": psnr(image, reference, background)}
        if k > 0:
            frame["adjacent_psnr_lod"] = psnr(image, with_lod[k - 1][0], background)
            frame["adjacent_psnr_strands"] = psnr(reference, with_strands[k - 1][0], background)
        frames.append(frame)

    # Draw time at the far view, settled selection.
    region_3d.view_distance = float(distances[-1])
    timings = {}
    for name, width_px, enabled in (("no_hair", 2.0, False), ("lod", 2.0, True), ("all_strands", 1e-3, True)):
        settings.enabled = enabled
        settings.width_px = width_px
        settings.vertex_tolerance_px = default_tolerance if width_px >= 1.0 else 0.0
        preview.views.clear()
        for _ in range(12):
            redraw(window, area, region)
        # Drawn in full each time (an unchanged view only composites the preview's hair layer again).
        timings[name] = 1e3 * min(redraw(window, area, region, 10, before=preview.draw_again) for _ in range(3))
    # The first frame builds the vertex buffers and the first batches: the per-frame figure is the others'.
    later_select = [times[k] for times in select_rounds for k in range(1, args.frames)]
    result = {"strands": len(strands), "build_seconds": build_seconds,
              "select_ms_median": float(np.median(later_select)), "select_ms_max": float(np.max(later_select)),
              "select_frames_over_1ms": f"{sum(t > 1.0 for t in later_select)} of {len(later_select)}",
              "clusters": asset.cluster_count, "levels": [len(level.n_total) for level in asset.levels], "frames": frames,
              "far_frame_ms": timings,
              "far_hair_ms_ratio": (timings["all_strands"] - timings["no_hair"]) /
                                   max(timings["lod"] - timings["no_hair"], 1e-3)}
    window_steps.report(result, args.out)


window_steps.run_once(lambda: run(parse_args()))
