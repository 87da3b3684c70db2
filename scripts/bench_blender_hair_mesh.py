"""Times the Generate Strands operator: hair mesh object -> hair Curves object.

Run: blender -b --factory-startup --python scripts/bench_blender_hair_mesh.py [-- --count 100000 --vertices 17]
Prints one JSON object: median seconds of 3 runs of the whole operator, of the strand generation
alone and of reading the hair mesh object, on a hair mesh extruded from a quarter of a sphere; and
of one live preview update after a vertex edit (in-place rewrite), at the preview's strand limit
and with the limit raised to --count.
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
    from hairlod.blender.hair_mesh import hair_mesh_from_object
    from hairlod.hairmesh import generate_strands

    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
    sphere = bpy.context.active_object
    centres = np.empty((len(sphere.data.polygons), 3), np.float32)
    sphere.data.polygons.foreach_get("center", centres.ravel())
    # A scalp-like patch: the upper half of the sphere on the side x > 0.
    sphere.data.polygons.foreach_set("select", (centres[:, 2] > 0) & (centres[:, 0] > 0))
    bpy.ops.hairlod.hair_mesh_from_faces(layers=4, length=0.5)
    hair_obj = bpy.context.active_object
    settings = dict(count=args.count, vertices=str(args.vertices), curl_radius=0.01, clump_amount=0.3)

    hair_mesh = hair_mesh_from_object(hair_obj)
    result = {
        "count": args.count,
        "vertices": args.vertices,
        "hair_mesh_faces": hair_mesh.face_count,
        "hair_mesh_layers": hair_mesh.layer_count,
        "read_hair_mesh_s": median_seconds(lambda: hair_mesh_from_object(hair_obj)),
        "generate_s": median_seconds(lambda: generate_strands(hair_mesh, count=args.count, vertices=args.vertices)),
        "operator_s": median_seconds(lambda: bpy.ops.hairlod.generate_strands(**settings)),
    }
    from hairlod.blender import hair_mesh_preview

    for key, limit in (("preview_update_s", hair_mesh_preview.PREVIEW_STRAND_LIMIT), ("preview_update_full_s", args.count)):
        hair_mesh_preview.PREVIEW_STRAND_LIMIT = limit
        hair_obj.hairlod_strands.live_preview = False
        hair_obj.hairlod_strands.live_preview = True
        result[key] = median_seconds(lambda: _edit_and_update(hair_obj), repeats=5)
    print(json.dumps(result))


def _edit_and_update(obj):
    obj.data.vertices[-1].co.z += 1e-3
    obj.data.update()
    bpy.context.view_layer.update()


main()
