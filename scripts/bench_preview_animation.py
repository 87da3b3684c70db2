"""Benchmarks the viewport LoD preview on animated hair in a real Blender window (run under Xvfb).

Run: xvfb-run -a -s '-screen 0 1280x720x24' blender --factory-startup --python scripts/bench_preview_animation.py
     [-- --count 100000 --frames 12 --guides 256 --distance 1.5 --strand-coverage on --hair nod --out FILE.json]
Generates --count strands (17 points) in examples/data/wavy_cap.hairmesh.json as a hair Curves object
whose Geometry Nodes modifier nods it (a keyframed Transform, 0 to 0.5 rad over --frames frames), or
with --hair twisted-head --count strands of 16 points attached to a UV-sphere head that a keyframed
Simple Deform twists (tests/blender/hair_fixtures.twisted_head_hair; the strands follow their
surface, or with --surface-follow off the guides, as hair not attached would),
builds its LoD with Build Hair LoD (6 levels) and, seen from the side at --distance times the hair's
size, plays the frames three ways: the LoD preview (eps_w
2 px), the preview drawing every strand, and Blender drawing the evaluated strands itself (preview
off). Per frame it times the frame change (Blender's evaluation plus the preview's handler reading the
guides) and one redraw, and keeps the preview's own timings: reading the guides, skinning (the maps
and the selection geometry), uploading the maps, selection and draw. It also times redraws of a frame
that does not change (the static frame), and captures each frame to report the adjacent-frame PSNR of
the LoD and of every strand over the hair (the paper's Fig. 9 measure of popping). Prints one JSON
object of medians.
"""

import argparse
import os
import statistics
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
NOD = 0.5  # radians at the last frame


def parse_args():
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=100000)
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--guides", type=int, default=256)
    parser.add_argument("--distance", type=float, default=1.5, help="camera distance in hair sizes")
    parser.add_argument("--strand-coverage", choices=("on", "off"), default="on",
                        help="the preview's Strand Coverage (default on, the panel's default)")
    parser.add_argument("--hair", choices=("nod", "twisted-head"), default="nod")
    parser.add_argument("--surface-follow", choices=("on", "off"), default="on",
                        help="twisted-head: the strands follow their surface (default), or only the guides")
    parser.add_argument("--out")
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def median(values):
    return statistics.median(values) if values else None


def run(args):
    import addon_utils

    addon_utils.enable("hairlod", default_set=True)
    import hairlod
    from hairlod import hairmesh
    from hairlod.blender.curves import curves_to_strands, strands_to_curves
    from hairlod.blender.preview import lod_preview

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, args.frames
    scene.frame_set(1)
    from hair_fixtures import add_keyframed_rotation, twisted_head_hair  # tests/blender/hair_fixtures.py

    if args.hair == "nod":
        strands = hairlod.generate_strands(hairmesh.read(HAIR_MESH), count=args.count, vertices=17, seed=1)
        obj = strands_to_curves(strands, "Hair")
        add_keyframed_rotation(obj, ((1, (0.0, 0.0, 0.0)), (args.frames, (NOD, 0.0, 0.0))), name="Nod")
    else:
        obj, _ = twisted_head_hair(args.count, args.frames)
        strands = curves_to_strands(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    add_sun(scene)
    start = time.perf_counter()
    bpy.ops.hairlod.build_lod(guides=args.guides, levels=6, control_points=16, seed=0)
    build_seconds = time.perf_counter() - start
    settings = obj.hairlod_lod_preview
    preview = lod_preview.preview_of(obj)
    settings.strand_coverage = args.strand_coverage == "on"
    if args.surface_follow == "off":
        preview.surface = False  # as for hair not attached to a mesh: the strands follow the guides

    lower, upper = strands.points.min(axis=0), strands.points.max(axis=0)
    size = float(np.linalg.norm(upper - lower))
    window, area, region, region_3d = bare_viewport(size)
    region_3d.view_location = 0.5 * (lower + upper)
    region_3d.view_rotation = (0.5, 0.5, 0.5, 0.5)  # from the side: the nod turns the image
    region_3d.view_distance = args.distance * size
    out_dir = os.environ.get("TMPDIR", "/tmp")

    obj.hide_set(True)
    redraw(window, area, region)
    background = capture(window, area, os.path.join(out_dir, "animation_background.png"))
    obj.hide_set(False)

    default_tolerance = settings.vertex_tolerance_px

    def play(name, enabled, width_px):
        settings.enabled, settings.width_px = enabled, width_px
        # Every strand means every control point too (the strands' vertex LoD off), as Blender draws them.
        settings.vertex_tolerance_px = default_tolerance if width_px >= 1.0 else 0.0
        scene.frame_set(args.frames)  # leave the rest pose first: frame 1 is a real change too
        redraw(window, area, region)
        rows, images = [], []
        for frame in range(1, args.frames + 1):
            start = time.perf_counter()
            scene.frame_set(frame)
            changed = time.perf_counter()
            redraw(window, area, region, finish=True)
            drawn = time.perf_counter()
            row = {"frame_change_ms": 1e3 * (changed - start), "redraw_ms": 1e3 * (drawn - changed)}
            if enabled:
                row.update({key: value for key, value in preview.follow_stats.items() if key.endswith("_ms")})
                surface_status = preview.follow_stats.get("surface")
                row.update(select_ms=preview.stats["select_ms"], segments=preview.stats["segments"])
            rows.append(row)
            images.append(capture(window, area, os.path.join(out_dir, f"animation_{name}_{frame}.png")))
        # Drawn in full (an unchanged frame only composites the preview's hair layer again).
        static = [1e3 * redraw(window, area, region, finish=True, before=preview.draw_again if enabled else None)
                  for _ in range(5)]
        summary = {key: median([row[key] for row in rows if key in row])
                   for key in ("frame_change_ms", "redraw_ms", "read_ms", "skin_ms", "upload_ms", "select_ms", "segments")}
        summary["frame_ms"] = median([row["frame_change_ms"] + row["redraw_ms"] for row in rows])
        summary["static_redraw_ms"] = median(static)
        if enabled:
            summary["surface"] = surface_status
        summary["adjacent_psnr"] = median([psnr(images[k], images[k - 1], background) for k in range(1, len(images))])
        return summary, images

    lod_summary, lod_images = play("lod", True, 2.0)
    strands_summary, strand_images = play("strands", True, 0.01)
    blender_summary, blender_images = play("blender", False, 2.0)
    result = {"hair": args.hair, "strands": len(strands), "frames": args.frames, "distance": args.distance, "build_seconds": build_seconds,
              "clusters": preview.asset.cluster_count, "levels": len(preview.asset.levels) + 1,
              "preview_lod": lod_summary, "preview_all_strands": strands_summary, "blender_draws_strands": blender_summary,
              "lod_vs_strands_psnr": median([psnr(a, b, background) for a, b in zip(lod_images, strand_images)]),
              "adjacent_psnr_gap_db": lod_summary["adjacent_psnr"] - strands_summary["adjacent_psnr"],
              "playback_speedup_vs_blender": blender_summary["frame_ms"] / lod_summary["frame_ms"]}
    window_steps.report(result, args.out)


window_steps.run_once(lambda: run(parse_args()))
