"""The renderer calls the Embree it was built and bundled with, even when the process has already
loaded another library exporting Embree's C names globally (as Blender 4.2+ does with its own
libembree4.so.4, whose functions share Embree 3's names): render/embree.h looks the functions up in
the core's own libraries. Here a decoy library whose rtc* functions abort is loaded with RTLD_GLOBAL
before the core; a core that bound to the global scope would call the decoy and die."""

import os
import shutil
import subprocess
import sys
import textwrap

from conftest import REPO

DECOY = """
#include <stdio.h>
#include <stdlib.h>
#define DECOY(name) void name(void) { fprintf(stderr, "decoy " #name " called\\n"); abort(); }
DECOY(rtcNewDevice) DECOY(rtcNewScene) DECOY(rtcNewGeometry) DECOY(rtcCommitScene)
DECOY(rtcIntersect1) DECOY(rtcOccluded1) DECOY(rtcReleaseDevice) DECOY(rtcSetDeviceErrorFunction)
"""

RENDER = textwrap.dedent("""
    import ctypes, os, sys
    ctypes.CDLL(sys.argv[1], mode=os.RTLD_NOW | ctypes.RTLD_GLOBAL)
    sys.path.insert(0, sys.argv[2])
    import numpy as np
    from hairlod import bench, render
    hair = bench.synthetic_hair(50, 8)
    result = render.render(hair, "pt", "mid", 16, 1, seed=1)
    print("hair pixels", int((result["image"].sum(axis=-1) > 0).sum()))
""")


def test_render_ignores_a_global_decoy_embree(tmp_path):
    compiler = shutil.which("cc") or shutil.which("gcc")
    assert compiler is not None, "a C compiler builds the decoy library (build-essential, make bootstrap)"
    source = tmp_path / "decoy.c"
    source.write_text(DECOY)
    decoy = tmp_path / "libdecoy.so"
    subprocess.run([compiler, "-shared", "-fPIC", "-o", str(decoy), str(source)], check=True)
    done = subprocess.run([sys.executable, "-c", RENDER, str(decoy), str(REPO / "addon")],
                          capture_output=True, text=True, timeout=300, env={**os.environ, "PYTHONPATH": ""})
    assert done.returncode == 0, done.stderr[-2000:]
    assert "decoy" not in done.stderr
    assert int(done.stdout.split()[-1]) > 0, done.stdout
