"""Makes the bundled example hair meshes in examples/data/ (JSON, docs/hairmesh-format.md).

scalp_patch.hairmesh.json  a 4 x 3 patch of a spherical scalp (12 bundles, one a triangle pair
                           split from a pentagon) extruded into 4 layers that fall and curl
                           outwards, with a gentle curl + clump + frizz styling.
wavy_cap.hairmesh.json     a cap over the top of a sphere of radius 10 (16 x 4 quads around a
                           triangle fan at the crown), 6 layers of long hair falling under
                           gravity, styled with wave + twist + clump + frizz + trim.
Run from the repository root:  PYTHONPATH=addon /usr/bin/python3 examples/make_hair_meshes.py
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "addon"))

from hairlod import hairmesh  # noqa: E402

DATA = Path(__file__).resolve().parent / "data"
RADIUS = 10.0


def sphere_point(theta, phi):
    return RADIUS * np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def extrude(root, layers, length, droop):
    """Layers leave the scalp along its normal and bend down by droop * t^2 (t the layer fraction)."""
    normals = root / np.linalg.norm(root, axis=1, keepdims=True)
    result = []
    for layer in range(layers):
        t = layer / (layers - 1)
        result.append(root + normals * length * t - np.array([0.0, 0.0, droop]) * t * t)
    return np.array(result, dtype=np.float32)


def scalp_patch():
    columns, rows = 5, 4
    root = np.array([sphere_point(0.5 + 0.18 * j, -0.4 + 0.2 * i) for j in range(rows) for i in range(columns)])
    faces = [[j * columns + i, j * columns + i + 1, (j + 1) * columns + i + 1, (j + 1) * columns + i]
             for j in range(rows - 1) for i in range(columns - 1)]
    # One bundle is a pentagon (an extra vertex on its edge), split into a quad and a triangle on reading.
    extra = len(root)
    root = np.vstack([root, 0.5 * (root[0] + root[1])])
    faces[0] = [0, extra, 1, columns + 1, columns]
    layers = extrude(root, 4, 6.0, 4.0)
    uv = [[[float(v % columns) / (columns - 1), float(v // columns) / (rows - 1)] if v != extra else [0.125, 0.0]
           for v in face] for face in faces]
    styling = [
        {"op": "curl", "radius": 0.25, "frequency": 0.5, "randomness": 0.4},
        {"op": "clump", "amount": 0.5, "profile": 2.0},
        {"op": "frizz", "amplitude": 0.05, "frequency": 1.0},
    ]
    return layers, faces, uv, styling, 0.01


def wavy_cap():
    around, rings = 16, 4
    crown = np.array([sphere_point(0.0, 0.0)])
    ring_points = np.array([sphere_point(0.25 + 0.3 * j, 2 * np.pi * i / around) for j in range(rings + 1) for i in range(around)])
    root = np.vstack([crown, ring_points])
    faces = [[0, 1 + i, 1 + (i + 1) % around] for i in range(around)]
    for j in range(rings):
        for i in range(around):
            a, b = 1 + j * around + i, 1 + j * around + (i + 1) % around
            faces.append([a, a + around, b + around, b])
    layers = extrude(root, 6, 4.0, 22.0)
    styling = [
        {"op": "wave", "amplitude": 0.6, "frequency": 0.12, "randomness": 0.3},
        {"op": "twist", "rate": 0.01},
        {"op": "clump", "amount": 0.35, "profile": 1.5},
        {"op": "frizz", "amplitude": 0.08, "frequency": 0.8},
        {"op": "trim", "amount": 0.15},
    ]
    return layers, faces, None, styling, 0.012


def save(name, layers, faces, uv, styling, radius):
    sizes = np.array([len(face) for face in faces], dtype=np.int32)
    flat = np.array([v for face in faces for v in face], dtype=np.int32)
    uv_array = None if uv is None else np.array([pair for face in uv for pair in face], dtype=np.float32)
    mesh = hairmesh.HairMesh(layers, sizes, flat, uv_array)
    path = DATA / name
    hairmesh.write(path, mesh, hairmesh.styling_from_dicts(styling), radius)
    print(f"{path}: {mesh}, {path.stat().st_size} bytes")


if __name__ == "__main__":
    DATA.mkdir(exist_ok=True)
    save("scalp_patch.hairmesh.json", *scalp_patch())
    save("wavy_cap.hairmesh.json", *wavy_cap())
