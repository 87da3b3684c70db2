"""hairlod: strand hair to real-time level-of-detail assets.

The same package is a plain Python library (``import hairlod``), a command line
(``python3 -m hairlod``) and a Blender add-on. Only ``hairlod.blender`` imports ``bpy``.
"""

bl_info = {
    "name": "Hair LoD",
    "author": "hairlod developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Hair LoD",
    "description": "Strand hair to real-time level-of-detail assets",
    "category": "Object",
}

__version__ = ".".join(str(part) for part in bl_info["version"])

from ._native import load_core  # noqa: E402

_core = load_core(__name__)
from ._core import HairlodError, Strands  # noqa: E402
from . import io  # noqa: E402
from .hairmesh import HairMesh, generate_strands  # noqa: E402

__all__ = ["HairMesh", "HairlodError", "Strands", "__version__", "generate_strands", "io", "register", "unregister"]


def register():
    """Blender entry point: registers operators, properties and panels."""
    from .blender import register as register_blender

    register_blender()


def unregister():
    """Blender entry point: removes everything register() added."""
    from .blender import unregister as unregister_blender

    unregister_blender()
