"""Writes a short test animation of a hair file, for `hairlod lod --animation` and `hairlod bench
animation`: the hair at --frames frames of a head nod (a turn about the side axis through the top of
the hair) with a bend growing down the strands (each strand turns more towards its tip, so clusters
deform non-rigidly), as OUT_DIR/frame_0001.hair, frame_0002.hair, ...

Run: PYTHONPATH=addon python3 scripts/animate_hair.py IN OUT_DIR [--frames 8] [--nod 0.4] [--bend 0.3] [--up z]
--nod and --bend are the angles (radians) reached at the last frame; the first frame is the hair as read.
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "addon"))

from hairlod import Strands, io  # noqa: E402


def rotate_about_x(points, angle, pivot):
    """Points [N, 3] (z up) turned by `angle` [N] or scalar about the x axis through `pivot`."""
    c, s = np.cos(angle), np.sin(angle)
    p = points - pivot
    return np.stack([p[:, 0], c * p[:, 1] - s * p[:, 2], s * p[:, 1] + c * p[:, 2]], axis=1) + pivot


def frame_points(points, t, nod, bend):
    """The hair (z up) at animation time t in [0, 1]."""
    lower, upper = points.min(axis=0), points.max(axis=0)
    height = max(float(upper[2] - lower[2]), 1e-30)
    top = np.array([0.5 * (lower[0] + upper[0]), 0.5 * (lower[1] + upper[1]), upper[2]])
    depth = (upper[2] - points[:, 2]) / height  # 0 at the top of the hair, 1 at its lowest point
    bent = rotate_about_x(points, t * bend * depth, top)
    return rotate_about_x(bent, t * nod, top)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("input")
    parser.add_argument("out_dir")
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--nod", type=float, default=0.4, help="radians at the last frame (default 0.4)")
    parser.add_argument("--bend", type=float, default=0.3, help="radians at the tips at the last frame (default 0.3)")
    parser.add_argument("--up", choices=["y", "z"], default="z", help="the file's up axis (default z)")
    args = parser.parse_args()
    if args.frames < 2:
        parser.error("--frames must be >= 2")
    hair = io.read(args.input)
    # Work z-up: a y-up file has its y and z swapped (and back when written).
    order = [0, 2, 1] if args.up == "y" else [0, 1, 2]
    points = hair.points.astype(np.float64)[:, order]
    os.makedirs(args.out_dir, exist_ok=True)
    for frame in range(args.frames):
        moved = frame_points(points, frame / (args.frames - 1), args.nod, args.bend)[:, order]
        path = os.path.join(args.out_dir, f"frame_{frame + 1:04d}.hair")
        io.write(path, Strands(moved.astype(np.float32), hair.offsets, hair.radius))
    print(f"{args.input}: {args.frames} frames in {args.out_dir}")


if __name__ == "__main__":
    main()
