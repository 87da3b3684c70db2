"""Loads the compiled core as `<package>._core`, from wherever this copy of the package has it:

- beside the Python files (a source tree after `make build`, or the add-on zip for Blender 3.4-4.1,
  whose core brings its libraries in _core.libs/);
- or from the hairlod_native wheel that the Blender 4.2+ extension installs into its site-packages.

Not opened with RTLD_DEEPBIND: Blender allocates with jemalloc, and a deep-bound core would free that
memory with glibc's free (seen crashing Blender 4.3 at exit). The core calls Embree, whose C names
Blender's own Embree shares, through pointers looked up in its own libraries (render/embree.h).
"""

import importlib
import importlib.util
import sys

WHEEL_MODULE = "hairlod_native._core"


def load_core(package):
    """The core module, registered as `<package>._core` so that `from . import _core` finds it."""
    name = package + "._core"
    if name in sys.modules:
        return sys.modules[name]
    if importlib.util.find_spec(name) is not None:
        return importlib.import_module(name)
    try:
        core = importlib.import_module(WHEEL_MODULE)
    except ModuleNotFoundError:
        version = f"cp{sys.version_info.major}{sys.version_info.minor}"
        raise ImportError(f"hairlod: no compiled core for this Python ({version}): build it (make build), or "
                          f"install the hairlod package made for {version}") from None
    sys.modules[name] = core
    return core
