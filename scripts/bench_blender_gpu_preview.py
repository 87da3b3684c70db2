"""Times one update of the Viewport Strands GPU preview: strand generation + GPU buffer fill.

Needs a window (the gpu module raises in -b): run under Xvfb,
  xvfb-run -a -s '-screen 0 1280x720x24' blender --factory-startup --python scripts/bench_blender_gpu_preview.py \\
      [-- --count 100000 --vertices 17]
Prints one JSON object: median seconds (5 runs) of regenerating after a hair-mesh edit (the cached
generator is rebuilt: styling frames, with the root sample sets reused), after a styling change
(generator kept), of the GPU buffer fill alone with the topology unchanged and changed (index buffer and ramp
rebuilt), and of drawing the batch once into an offscreen buffer (the upload to the GPU happens at
the first draw; Mesa llvmpipe under Xvfb, so this draw is software rasterisation).
"""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_bench_args import strand_arguments  # noqa: E402  (puts addon/ on sys.path too)

import addon_utils  # noqa: E402
import bpy  # noqa: E402
import numpy as np  # noqa: E402

from hairlod.bench import median_seconds  # noqa: E402


def main():
    args = strand_arguments()

    addon_utils.enable("hairlod", default_set=True)
    import gpu
    from mathutils import Matrix

    from hairlod.blender import hair_mesh_gpu_preview as preview
    from hairlod.blender.preview.strand_batch import StrandBatch

    for existing in list(bpy.data.objects):
        bpy.data.objects.remove(existing)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
    sphere = bpy.context.active_object
    centres = np.empty((len(sphere.data.polygons), 3), np.float32)
    sphere.data.polygons.foreach_get("center", centres.ravel())
    sphere.data.polygons.foreach_set("select", centres[:, 2] > 0)
    bpy.ops.hairlod.hair_mesh_from_faces(layers=4, length=0.5)
    obj = bpy.context.active_object
    settings = obj.hairlod_strands
    settings.count, settings.vertices = args.count, str(args.vertices)
    settings.curl_radius, settings.clump_amount, settings.frizz_amplitude = 0.01, 0.3, 0.005
    settings.viewport_strands = True
    state = preview.preview_state(obj)

    def after_edit():
        state.mesh_key = state.mesh_key + (len(state.mesh_key),)  # as if the mesh changed
        preview.regenerate(obj, state, 1.0)
        return state.timings

    def after_settings():
        settings.curl_radius = 0.02 if settings.curl_radius < 0.015 else 0.01  # styling: the generator is kept
        preview.regenerate(obj, state, 1.0)
        return state.timings

    def timings_of(update):
        runs = [dict(update()) for _ in range(5)]
        return {key: float(np.median([run[key] for run in runs])) for key in runs[0]}

    edit = timings_of(after_edit)
    settings_change = timings_of(after_settings)
    strands = state.generator.generate(vertices=args.vertices)
    points, tangents, offsets = strands.points, strands.attribute("tangent"), strands.offsets
    batch = StrandBatch()
    batch.update(points, tangents, offsets)
    fill_same = median_seconds(lambda: batch.update(points, tangents, offsets), 5)

    def fill_new():
        batch._offsets = None
        batch.update(points, tangents, offsets)

    fill_changed = median_seconds(fill_new, 5)
    offscreen = gpu.types.GPUOffScreen(512, 512)

    def draw_once():
        batch.update(points, tangents, offsets)
        with offscreen.bind():
            batch.draw(Matrix.Identity(4), (0.0, 0.0, 1.0), preview.ROOT_COLOUR, preview.TIP_COLOUR)
            offscreen.texture_color.read()  # waits for the draw

    draw_s = median_seconds(draw_once, 3) - fill_same
    print(json.dumps({
        "count": args.count, "vertices": args.vertices, "points": int(len(points)),
        "update_after_edit": edit, "update_after_settings": settings_change,
        "update_after_edit_ms": 1e3 * (edit["generate_s"] + edit["upload_s"]),
        "update_after_settings_ms": 1e3 * (settings_change["generate_s"] + settings_change["upload_s"]),
        "buffer_fill_s": fill_same, "buffer_fill_new_topology_s": fill_changed,
        "first_draw_llvmpipe_s": draw_s,
    }))
    sys.stdout.flush()
    os._exit(0)


main()
