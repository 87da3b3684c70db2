"""Benchmarks what an artist waits for around Build Hair LoD, in a real Blender window (run under Xvfb).

Run: xvfb-run -a -s '-screen 0 1280x720x24' blender --factory-startup --python scripts/bench_preview_latency.py
     [-- --count 100000 --runs 3 --strand-coverage on --out FILE.json]
Generates --count strands of 17 points in examples/data/wavy_cap.hairmesh.json as a hair Curves object in
the default scene (its grey world, one light) and measures, per run: the LoD build run directly
(hairlod.blender.pipeline.build_lod: read the curves, build, pack into the object, in this process), its
export with the BCSDF tables baked (pipeline.export_lod), the same build from the button (the modal operator, from invoke until the asset is packed and its preview attached), and the first frame of the preview after it (from the
asset being packed to the first draw of the preview ending, and that draw's own time, with the part of
it spent making vertex buffers and tables, which a faster GPU does not shorten), and the median of the
next 3 draws of the same view (drawing that frame once everything is set up: the floor of the first
frame on this GPU), then 3 more with each pass of the draw timed on its own (the levels into the hair
layer, the strands' shading there, the sample added to the layer's sums, the composite into the
viewport; medians). These draws are made in full (LodPreview.draw_again): a redraw of a view where
nothing changed adds one more sample of the viewport's anti-aliasing to the hair layer, and once the
layer holds them all only composites it again. The benchmark waits for the viewport to be at rest (no redraw for 3 s) before each build.
Every draw timed waits for the GPU to finish it (a pixel read back). Then, for
comparison, whole redraws of the viewport region (3 each, median) with the preview on (drawn in full,
and unchanged with every sample held: composited again) and with Blender drawing the strands itself (the preview off). Prints one JSON
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
import gpu

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import window_steps  # noqa: E402  (scripts/window_steps.py)
from viewport_capture import RedrawTimes, redraw  # noqa: E402  (scripts/viewport_capture.py)
HAIR_MESH = os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json")
POLL = 0.02
LATER_DRAWS = 3  # redraws of the same view after the first, their median reported
QUIET = 3.0  # seconds without a redraw: the viewport at rest (longer than a redraw of every strand)


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
    from hairlod.blender.preview import hair_layer, lod_preview

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
    # When the button's build ends: the asset packed into the object and its preview attached (the
    # operator's last step). Timed where it happens: the poll below may first see the asset after
    # Blender has already redrawn the viewport in the same turn of its event loop.
    attached = []
    original_attach = lod_preview.attach

    def timed_attach(*attach_args, **attach_kwargs):
        result = original_attach(*attach_args, **attach_kwargs)
        attached.append(time.perf_counter())
        return result

    lod_preview.attach = timed_attach
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
    # The passes of a draw (lod_preview.LodPreview.draw): the hair levels into the hair layer, the strands'
    # shading in it, the sample added to the layer's sums, the composite into the viewport; each timed until the framebuffer it drew into has
    # been drawn (the layer's, its shading framebuffer, the viewport's), only while timing_passes[0].
    pass_times = {}
    timing_passes = [False]

    def read_pixel(framebuffer):
        framebuffer.read_color(0, 0, 1, 1, 4, 0, 'UBYTE')

    def timed_pass(cls, method_name, key, framebuffer_of):
        original = getattr(cls, method_name)

        def method(instance, *method_args, **method_kwargs):
            if not timing_passes[0]:
                return original(instance, *method_args, **method_kwargs)
            read_pixel(gpu.state.active_framebuffer_get())
            start = time.perf_counter()
            result = original(instance, *method_args, **method_kwargs)
            read_pixel(framebuffer_of(instance))
            pass_times.setdefault(key, []).append(time.perf_counter() - start)
            return result
        setattr(cls, method_name, method)
        return original

    active = lambda instance: gpu.state.active_framebuffer_get()  # noqa: E731
    pass_originals = [
        (lod_preview.LodPreview, "_draw_levels", timed_pass(lod_preview.LodPreview, "_draw_levels", "levels", active)),
        (hair_layer.HairLayer, "shade_strands",
         timed_pass(hair_layer.HairLayer, "shade_strands", "strand_shading", lambda layer: layer._shading_framebuffer)),
        (hair_layer.HairLayer, "accumulate",
         timed_pass(hair_layer.HairLayer, "accumulate", "accumulate", lambda layer: layer._accumulation_framebuffer)),
        (hair_layer.HairLayer, "composite", timed_pass(hair_layer.HairLayer, "composite", "composite", active)),
    ]
    viewport_draws = RedrawTimes()
    runs = []
    for _ in range(args.runs):
        yield from viewport_draws.at_rest(QUIET)
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
        # The viewport settles first: after a change Blender redraws it once per sample of its
        # anti-aliasing (Preferences > Viewport > Anti-Aliasing, 8 by default), each drawing every
        # strand of the source again; an artist presses the button in a viewport at rest.
        yield from viewport_draws.at_rest(QUIET)
        draws.clear()
        attached.clear()
        viewport_draws.clear()
        setup.clear()
        start = time.perf_counter()
        with bpy.context.temp_override(window=window, area=area):
            bpy.ops.hairlod.build_lod('INVOKE_DEFAULT')
        while PACKED_PROPERTY not in source or not attached:
            yield POLL
        packed = attached[0]
        redraws_during_build = len(viewport_draws)
        area.tag_redraw()
        while not draws:
            yield POLL
        first_start, first_end = draws[0]
        first_setup = dict(setup)  # what the first draw spent in them (later draws add nothing: cached)
        preview = lod_preview.preview_of(source)

        def draw_again():
            """A step generator: the same view drawn again in full (LodPreview.draw_again: the preview
            would otherwise composite the unchanged hair layer); that draw's (start, end)."""
            preview.draw_again()
            area.tag_redraw()
            count = len(draws)
            while len(draws) == count:
                yield POLL
            return draws[count]

        # The same view drawn again, nothing to set up: what the GPU (llvmpipe) takes to draw the frame.
        later = []
        for _ in range(LATER_DRAWS):
            begin, end = yield from draw_again()
            later.append(end - begin)
        later_draw = statistics.median(later)
        # The same view again, each pass of the draw timed on its own (a pixel of what it drew read back
        # after it): where a later draw's time goes.
        pass_times.clear()
        timing_passes[0] = True
        for _ in range(LATER_DRAWS):
            yield from draw_again()
        timing_passes[0] = False
        later_passes = {name: statistics.median(seconds) for name, seconds in pass_times.items()}
        region = next(r for r in area.regions if r.type == 'WINDOW')
        region_redraws = {}
        for name, enabled, again in (("preview", True, True), ("preview_unchanged", True, False),
                                     ("blender", False, False)):
            source.hairlod_lod_preview.enabled = enabled
            # The display change settles. Unchanged, the preview's hair layer then holds every sample of
            # the viewport's anti-aliasing, as after Blender's redraws at rest, and only composites it
            # again; Blender's own drawing is timed per sample of its anti-aliasing, each of which draws
            # the strands.
            redraw(window, area, region, finish=True,
                   iterations=lod_preview.anti_aliasing_samples() if name == "preview_unchanged" else 1)
            region_redraws[name] = statistics.median(
                redraw(window, area, region, finish=True, before=preview.draw_again if again else None)
                for _ in range(LATER_DRAWS))
        source.hairlod_lod_preview.enabled = True
        runs.append({"direct_build_s": direct, "export_bake_s": export, "button_build_s": packed - start,
                     "button_over_direct": (packed - start) / direct, "first_frame_s": first_end - packed,
                     "first_draw_s": first_end - first_start, "first_draw_setup_s": sum(first_setup.values()),
                     "later_draw_s": later_draw,
                     **{f"later_{name}_s": later_passes.get(name, 0.0) for name in ("levels", "strand_shading", "accumulate", "composite")},
                     "preview_region_redraw_s": region_redraws["preview"],
                     "preview_unchanged_region_redraw_s": region_redraws["preview_unchanged"],
                     "blender_region_redraw_s": region_redraws["blender"],
                     **{f"setup_{name.lstrip('_')}_s": first_setup.get(name, 0.0) for name in setup_methods},
                     "viewport_redraws_during_build": redraws_during_build})
        print(json.dumps(runs[-1]), flush=True)
    lod_preview.LodPreview.draw = original_draw
    lod_preview.attach = original_attach
    for cls, name, method in pass_originals:
        setattr(cls, name, method)
    for name, method in originals.items():
        setattr(lod_preview.LodPreview, name, method)
    viewport_draws.remove()
    result = {"blender": bpy.app.version_string, "strands": args.count, "runs": runs,
              "median": {key: statistics.median(run[key] for run in runs) for key in runs[0]}}
    window_steps.report(result, args.out)


window_steps.run(steps(parse_args()))
