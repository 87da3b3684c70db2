"""The legacy add-on zip (scripts/build_addon.py) installs into a fresh user scripts folder and works from
there, its compiled core and bundled libraries included (the extension: tests/packages/)."""

import os
import subprocess
import sys

import bpy
import numpy as np
import pytest

from conftest import ADDON_DIR, REPO_ROOT

# The add-on under test is the installed copy, not the source tree that conftest (or a PYTHONPATH
# from the environment) put on sys.path.
sys.path[:] = [entry for entry in sys.path if os.path.abspath(entry) != os.path.abspath(ADDON_DIR)]


@pytest.fixture
def user_scripts(tmp_path, monkeypatch):
    scripts = tmp_path / "user_scripts"
    scripts.mkdir()
    monkeypatch.setenv("BLENDER_USER_SCRIPTS", str(scripts))
    assert bpy.utils.user_resource('SCRIPTS') == str(scripts)
    return scripts


@pytest.fixture
def addon_zip(tmp_path):
    built = subprocess.run([sys.executable, os.path.join(REPO_ROOT, "scripts", "build_addon.py"),
                            "--output-dir", str(tmp_path / "dist")],
                           capture_output=True, text=True, check=False)
    assert built.returncode == 0, built.stderr
    legacy = [path for path in built.stdout.split() if path.endswith("-legacy.zip")]
    assert len(legacy) == 1, built.stdout
    return legacy[0]


def test_zip_installs_enables_and_imports(empty_scene, user_scripts, addon_zip, shared_data):
    import addon_utils

    assert "hairlod" not in sys.modules
    assert os.path.basename(addon_zip).startswith("hairlod-0.1.0-")
    assert bpy.ops.preferences.addon_install(filepath=addon_zip) == {'FINISHED'}
    installed = user_scripts / "addons" / "hairlod"
    assert not (installed / "blender_manifest.toml").exists()
    assert not list(installed.rglob("__pycache__"))
    assert list((installed / "_core.libs").glob("libembree*-hairlod-*"))

    assert bpy.ops.preferences.addon_enable(module="hairlod") == {'FINISHED'}
    import hairlod

    assert os.path.dirname(hairlod.__file__) == str(installed)
    assert os.path.dirname(hairlod._core.__file__) == str(installed)
    assert "hairlod" in {addon.module for addon in bpy.context.preferences.addons}

    path = str(shared_data / "Bangs_100.hair")
    assert bpy.ops.hairlod.import_hair(filepath=path) == {'FINISHED'}
    obj = bpy.context.active_object
    assert obj.name == "Bangs_100" and len(obj.data.curves) == 100 and len(obj.data.points) == 1165
    points = np.empty((1165, 3), np.float32)
    obj.data.attributes["position"].data.foreach_get("vector", points.ravel())
    np.testing.assert_array_equal(points, hairlod.io.read(path).points)

    assert addon_utils.disable("hairlod", default_set=True) is None
    assert not hasattr(bpy.types, "HAIRLOD_OT_import_hair")
