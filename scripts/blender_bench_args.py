"""What the strand benchmarks that run inside Blender share (scripts/bench_blender_gpu_preview.py,
scripts/bench_blender_hair_mesh.py): the package on sys.path, and --count / --vertices after '--'."""

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "addon"))


def strand_arguments():
    """The arguments after Blender's own: --count strands (default 100000), --vertices per strand (17)."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=100000)
    parser.add_argument("--vertices", type=int, default=17)
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
