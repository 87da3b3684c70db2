"""Benchmarks what an artist waits for around Build Hair LoD, in a real Blender window (run under Xvfb).

Run: xvfb-run -a -s '-screen 0 1280x720x24' blender --factory-startup --python scripts/bench_preview_latency.py
     [-- --count 100000 --runs 3 --strand-coverage on --out FILE.json]
Generates --count strands of 17 points in examples/data/wavy_cap.hairmesh.json as a hair Curves object in
the default scene (its grey world, one light) and measures, per run: the LoD build run directly
(hairlod.blender.pipeline.build_lod: read the curves, build, pack into the object, in this process), its
export with the BCSDF tables baked (pipeline.export_lod), the same build from the button (the modal operator, from invoke until the asset is packed), and the first frame of the preview after it (from the
asset being packed to the first draw of the preview ending, and that draw's own time, with the part of
it spent making vertex buffers and tables, which a faster GPU does not shorten), and the median of the
next 3 draws of the same view (drawing that frame once everything is set up: the floor of the first
frame on this GPU). Every draw timed waits for the GPU to finish it (a pixel read back). Then, for
comparison, whole redraws of the viewport region (3 each, median) with the preview on and with Blender
drawing the strands itself (the preview off). Prints one JSON
object with every run and the medians; the ratio of button to direct build in the same run.
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time

import bpy

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import window_steps  # noqa: E402  (scripts/window_steps.py)
from viewport_capture import redraw  # noqa: E402  (scripts/viewport_capture.py)
HAIR_MESH = os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json")
POLL = 0.02
LATER_DRAWS = 3  # redraws of the same view after the first, their median reported


def parse_args():
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=100000)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--strand-coverage", choices=("on", "off"), default="on",
                        help="the preview's Strand Coverage (default on, the panel's default)")
    parser.add_argument("--out")
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def steps(args):
    import addon_utils

    addon_utils.enable("hairlod", default_set=True)
    import hairlod
    from hairlod import hairmesh
    from hairlod.blender.curves import strands_to_curves
    from hairlod.blender import pipeline
    from hairlod.blender.packed_asset import PACKED_PROPERTY
    from hairlod.blender.preview import lod_preview

    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    strands = hairlod.generate_strands(hairmesh.read(HAIR_MESH), count=args.count, vertices=17, seed=1)
    source = strands_to_curves(strands, "Hair")
    source.hairlod_lod_preview.strand_coverage = args.strand_coverage == "on"
    bpy.context.view_layer.objects.active = source
    draws = []
    original_draw = lod_preview.LodPreview.draw

    def timed_draw(preview, *draw_args):
        start = time.perf_counter()
        result = original_draw(preview, *draw_args)
        # Until the GPU has drawn what the preview queued: a software GPU (llvmpipe) may still be
        # rasterising when the draw calls return.
        lod_preview.gpu_finish()()
        draws.append((start, time.perf_counter()))
        return result

    lod_preview.LodPreview.draw = timed_draw
    # The first frame's work that a faster GPU does not shorten: the vertex arrays and their upload, the
    # BCSDF tables and the world's response table (seconds per method, summed within a draw).
    setup = {}
    setup_methods = ("_build_vertex_buffers", "bcsdf_textures", "world_lighting")
    originals = {name: getattr(lod_preview.LodPreview, name) for name in setup_methods}

    def timed_method(name):
        def method(preview, *method_args):
            start = time.perf_counter()
            result = originals[name](preview, *method_args)
            setup[name] = setup.get(name, 0.0) + time.perf_counter() - start
            return result
        return method

    for name in setup_methods:
        setattr(lod_preview.LodPreview, name, timed_method(name))
    viewport_draws = []
    counter = bpy.types.SpaceView3D.draw_handler_add(lambda: viewport_draws.append(time.perf_counter()), (), 'WINDOW',
                                                     'POST_PIXEL')
    runs = []
    for _ in range(args.runs):
        start = time.perf_counter()
        pipeline.build_lod(source)
        direct = time.perf_counter() - start
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            pipeline.export_lod(source, folder, bake=True)
            export = time.perf_counter() - start
        if PACKED_PROPERTY in source:
            del source[PACKED_PROPERTY]
        lod_preview.detach(source.name)
        yield 0.5
        draws.clear()
        viewport_draws.clear()
        setup.clear()
        start = time.perf_counter()
        with bpy.context.temp_override(window=window, area=area):
            bpy.ops.hairlod.build_lod('INVOKE_DEFAULT')
        while PACKED_PROPERTY not in source:
            yield POLL
        packed = time.perf_counter()
        redraws_during_build = len(viewport_draws)
        area.tag_redraw()
        while not draws:
            yield POLL
        first_start, first_end = draws[0]
        first_setup = dict(setup)  # what the first draw spent in them (later draws add nothing: cached)
        # The same view drawn again, nothing to set up: what the GPU (llvmpipe) takes to draw the frame.
        while len(draws) < 1 + LATER_DRAWS:
            area.tag_redraw()
            count = len(draws)
            while len(draws) == count:
                yield POLL
        later_draw = statistics.median(end - begin for begin, end in draws[1:1 + LATER_DRAWS])
        region = next(r for r in area.regions if r.type == 'WINDOW')
        region_redraws = {}
        for name, enabled in (("preview", True), ("blender", False)):
            source.hairlod_lod_preview.enabled = enabled
            redraw(window, area, region, finish=True)  # the display change settles
            region_redraws[name] = statistics.median(redraw(window, area, region, finish=True) for _ in range(LATER_DRAWS))
        source.hairlod_lod_preview.enabled = True
        runs.append({"direct_build_s": direct, "export_bake_s": export, "button_build_s": packed - start,
                     "button_over_direct": (packed - start) / direct, "first_frame_s": first_end - packed,
                     "first_draw_s": first_end - first_start, "first_draw_setup_s": sum(first_setup.values()),
                     "later_draw_s": later_draw, "preview_region_redraw_s": region_redraws["preview"],
                     "blender_region_redraw_s": region_redraws["blender"],
                     **{f"setup_{name.lstrip('_')}_s": first_setup.get(name, 0.0) for name in setup_methods},
                     "viewport_redraws_during_build": redraws_during_build})
        print(json.dumps(runs[-1]), flush=True)
    lod_preview.LodPreview.draw = original_draw
    for name, method in originals.items():
        setattr(lod_preview.LodPreview, name, method)
    bpy.types.SpaceView3D.draw_handler_remove(counter, 'WINDOW')
    result = {"blender": bpy.app.version_string, "strands": args.count, "runs": runs,
              "median": {key: statistics.median(run[key] for run in runs) for key in runs[0]}}
    window_steps.report(result, args.out)


window_steps.run(steps(parse_args()))
