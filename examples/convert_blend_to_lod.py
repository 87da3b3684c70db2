"""Converts every hair Curves object of a .blend into an LoD asset and exports it: a CI-style script.

    blender -b scenes/hair.blend --python examples/convert_blend_to_lod.py -- --out build/lod [--guides K
        --levels 6 --control-points 16 --seed 0 --no-bake --save]

For each Curves object it builds the LoD (hairlod.blender.pipeline.build_lod: guides, clusters,
elliptical thick hairs, one Curves object per level, the asset packed into the object) and writes
<out>/<object name>/lod (one .hair of thick hairs per level, manifest, arrays) and
<out>/<object name>/bcsdf (the aggregated BCSDF's tables baked for the object's Principled Hair BSDF).
--save writes the .blend back with the packed assets. Prints one JSON object; exits 1 naming the
object and the problem if any conversion fails, 2 on bad arguments.
"""

import argparse
import json
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "addon"))


def parse_args():
    parser = argparse.ArgumentParser(prog="convert_blend_to_lod.py")
    parser.add_argument("--out", required=True, help="output folder (one sub-folder per Curves object)")
    parser.add_argument("--guides", type=int, default=0, help="guide hairs (default 0: one per 128 strands, 16 to 256)")
    parser.add_argument("--levels", type=int, default=6)
    parser.add_argument("--control-points", type=int, default=16)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-bake", action="store_true", help="skip the BCSDF tables")
    parser.add_argument("--save", action="store_true", help="save the .blend with the packed assets")
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def main():
    import addon_utils

    args = parse_args()
    addon_utils.enable("hairlod", default_set=True)
    from hairlod.blender import pipeline

    objects = [obj for obj in bpy.data.objects if obj.type == 'CURVES']
    results, failures = [], []
    for obj in objects:
        start = time.perf_counter()
        try:
            pipeline.build_lod(obj, guides=args.guides, levels=args.levels, control_points=args.control_points,
                               seed=args.seed)
            summary = pipeline.export_lod(obj, os.path.join(args.out, bpy.path.clean_name(obj.name)),
                                          bake=not args.no_bake)
        except (ValueError, RuntimeError, OSError) as error:
            failures.append(f"{obj.name}: {error}")
            continue
        summary["seconds"] = time.perf_counter() - start
        results.append(summary)
    if args.save and bpy.data.filepath:
        bpy.ops.wm.save_mainfile()
    print(json.dumps({"blend": bpy.data.filepath, "objects": results, "failed": failures}))
    for failure in failures:
        print(f"convert_blend_to_lod.py: {failure}", file=sys.stderr)
    sys.stdout.flush()
    os._exit(1 if failures else 0)


main()
