"""Makes the bundled default input, examples/data/bob.hair: a deterministic bob haircut.

2000 strands of 16 points grow from a spherical scalp (radius 100 units, about millimetres),
leave the scalp along its normal, fall under a smooth gravity profile and wave slightly.
Run from the repository root:  PYTHONPATH=addon /usr/bin/python3 examples/make_default_hair.py
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "addon"))

import hairlod  # noqa: E402
from hairlod import io  # noqa: E402

STRANDS = 2000
POINTS = 16
SCALP_RADIUS = 100.0
STRAND_LENGTH = 150.0
HAIR_RADIUS = 0.04


def scalp_roots(count):
    """Fibonacci-sphere points on the upper back of the scalp, with their normals."""
    golden = np.pi * (3.0 - np.sqrt(5.0))
    index = np.arange(count * 3)
    z = 1.0 - 2.0 * (index + 0.5) / (count * 3)
    ring = np.sqrt(1.0 - z * z)
    normals = np.stack([ring * np.cos(golden * index), ring * np.sin(golden * index), z], axis=1)
    keep = (normals[:, 2] > 0.05) & ((normals[:, 1] < 0.3) | (normals[:, 2] > 0.6))
    normals = normals[keep][:count]
    return normals * SCALP_RADIUS, normals


def grow(roots, normals, rng):
    t = np.linspace(0.0, 1.0, POINTS)[None, :, None]
    length = STRAND_LENGTH * rng.uniform(0.85, 1.0, (len(roots), 1, 1))
    # Leave the scalp along the normal, then bend down: a quadratic gravity profile.
    outward = normals[:, None, :] * (0.35 * length * t)
    drop = np.array([0.0, 0.0, -1.0]) * (length * t * t)
    phase = rng.uniform(0.0, 2.0 * np.pi, (len(roots), 1, 1))
    side = np.cross(normals, [0.0, 0.0, 1.0])
    side /= np.maximum(np.linalg.norm(side, axis=1, keepdims=True), 1e-9)
    wave = side[:, None, :] * (3.0 * np.sin(6.0 * np.pi * t + phase) * t)
    return roots[:, None, :] + outward + drop + wave


def main():
    rng = np.random.default_rng(2024)
    roots, normals = scalp_roots(STRANDS)
    points = grow(roots, normals, rng).reshape(-1, 3).astype(np.float32)
    taper = np.linspace(1.0, 0.3, POINTS, dtype=np.float32)
    radius = np.tile(HAIR_RADIUS * taper, len(roots))
    strands = hairlod.Strands.from_counts(points, np.full(len(roots), POINTS), radius)
    out = Path(__file__).resolve().parent / "data" / "bob.hair"
    io.write(out, strands)
    print(f"wrote {out}: {len(strands)} strands, {strands.point_count} points")


if __name__ == "__main__":
    main()
