"""Shared fixtures: the package from addon/, the shared hair files next to the repository and a small LoD
asset."""

import os
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "addon"))

SHARED_DATA = REPO.parent / "shared" / "data"
REAL_HAIR = REPO / "examples" / "data" / "tressfx" / "Ratboy_mohawk.tfx"


@pytest.fixture(scope="session")
def shared_data():
    """../shared/data/hairutil. It lives outside the repository (../shared/DESIGN.md): a clone without it skips
    the tests that need it with a message saying so (pytest -rs prints it), never passes them."""
    folder = SHARED_DATA / "hairutil"
    if not folder.is_dir():
        pytest.skip(f"shared test data {folder} is absent: clone the repository next to ../shared to run this test")
    return folder


@pytest.fixture(scope="session")
def real_hair():
    """A real hairstyle made outside the project, bundled with its MIT license so that every clone
    runs these tests: examples/data/tressfx/Ratboy_mohawk.tfx (AMD TressFX, 2228 strands x 32 points)."""
    from hairlod import io

    return io.read(str(REAL_HAIR))


@pytest.fixture(scope="session")
def blender():
    """The Blender binary for tests that run it headless (HAIRLOD_BLENDER, else `blender` on PATH).
    `make test` installs it (scripts/bootstrap.sh); plain pytest on a machine without Blender skips
    these tests with a message saying how to get them, never passes them."""
    binary = os.environ.get("HAIRLOD_BLENDER") or shutil.which("blender")
    if binary is None:
        pytest.skip("Blender is not installed: this test runs headless Blender (apt-get install blender, "
                    "or set HAIRLOD_BLENDER; `make test` installs it)")
    return binary


@pytest.fixture(scope="session")
def blender_version(blender):
    """(major, minor) of the `blender` fixture's Blender."""
    import re
    import subprocess

    first = subprocess.run([blender, "--version"], capture_output=True, text=True, timeout=120).stdout.splitlines()
    match = re.match(r"Blender (\d+)\.(\d+)", first[0] if first else "")
    assert match, f"cannot read the version of {blender}: {first[:1]}"
    return int(match.group(1)), int(match.group(2))


@pytest.fixture(scope="session")
def sphere_hair_lod():
    """(LodAsset, Strands): 600 short strands on a unit sphere, 4 levels at 6 control points."""
    import hairlod
    from hairlod import lod

    rng = np.random.default_rng(5)
    roots = rng.normal(size=(600, 3))
    roots /= np.linalg.norm(roots, axis=1, keepdims=True)
    steps = np.linspace(0.0, 1.0, 8)[None, :, None]
    points = roots[:, None, :] * (1.0 + 0.05 * steps) - 0.4 * steps * np.array([0.0, 0.0, 1.0])
    strands = hairlod.Strands.from_counts(points.reshape(-1, 3).astype(np.float32), np.full(600, 8),
                                          np.full(600 * 8, 0.003, np.float32))
    return lod.build_lod(strands, guides=10, levels=4, control_points=6, seed=2), strands
