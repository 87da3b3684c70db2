"""Times the Blender hair bridge: Strands -> Curves and Curves -> Strands.

Run: blender -b --factory-startup --python scripts/bench_blender_curves.py [-- --curves 100000 --points 16]
Prints one JSON object: median seconds of 5 runs each way.
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "addon"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

from hairlod import Strands  # noqa: E402
from hairlod.bench import median_seconds  # noqa: E402
from hairlod.blender.curves import curves_to_strands, strands_to_curves  # noqa: E402


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="bench_blender_curves.py")
    parser.add_argument("--curves", type=int, default=100_000)
    parser.add_argument("--points", type=int, default=16, help="points per curve")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)

    rng = np.random.default_rng(1)
    point_count = args.curves * args.points
    strands = Strands.from_counts(rng.random((point_count, 3), dtype=np.float32),
                                  np.full(args.curves, args.points, np.int64),
                                  rng.random(point_count, dtype=np.float32))

    def to_curves():
        obj = strands_to_curves(strands, "bench")
        curves = obj.data
        bpy.data.objects.remove(obj)
        bpy.data.hair_curves.remove(curves)

    reference = strands_to_curves(strands, "bench_reference")
    result = {
        "blender": bpy.app.version_string,
        "curves": args.curves,
        "points_per_curve": args.points,
        "repeats": args.repeats,
        "strands_to_curves_s": median_seconds(to_curves, args.repeats),
        "curves_to_strands_s": median_seconds(lambda: curves_to_strands(reference), args.repeats),
        "curves_to_strands_original_s": median_seconds(
            lambda: curves_to_strands(reference, evaluated=False), args.repeats),
    }
    print(json.dumps(result))


main()
