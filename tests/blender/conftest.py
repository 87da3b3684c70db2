"""Shared fixtures for the tests that run inside Blender (see pytest_main.py)."""

import os
import pathlib
import sys

import pytest

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
ADDON_DIR = os.path.join(REPO_ROOT, "addon")
SHARED_DATA_DIR = os.path.abspath(os.path.join(REPO_ROOT, os.pardir, "shared", "data"))

# The package under test comes from the source tree (test_install.py takes this out again).
sys.path.insert(0, ADDON_DIR)


@pytest.fixture(scope="session")
def shared_data():
    """../shared/data/hairutil. It lives outside the repository (../shared/DESIGN.md): a clone without it skips
    the tests that need it with a message saying so (pytest -rs prints it), never passes them."""
    folder = pathlib.Path(SHARED_DATA_DIR, "hairutil")
    if not folder.is_dir():
        pytest.skip(f"shared test data {folder} is absent: clone the repository next to ../shared to run this test")
    return folder


@pytest.fixture
def addon():
    """The hairlod add-on enabled from the source tree; disabled afterwards."""
    import addon_utils

    module = addon_utils.enable("hairlod", default_set=True, handle_error=_raise)
    assert module is not None, "addon_utils.enable('hairlod') failed"
    yield module
    addon_utils.disable("hairlod", default_set=True, handle_error=_raise)


@pytest.fixture
def empty_scene():
    """An empty scene (factory startup has a cube, a camera and a light)."""
    import bpy

    bpy.ops.wm.read_homefile(use_empty=True)
    return bpy.context.scene


def _raise(error):
    raise error
