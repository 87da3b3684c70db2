"""setuptools build of hairlod with the C++ extension built by CMake.

Offline: pip install --no-build-isolation .   (needs the Debian packages of scripts/bootstrap.sh)
"""

import os
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, find_packages, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).parent.resolve()


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """Configures and builds the `_core` target, placing it where setuptools expects it."""

    def build_extension(self, ext):
        output_dir = Path(self.get_ext_fullpath(ext.name)).parent.resolve()
        build_dir = Path(self.build_temp).resolve() / "cmake"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            f"-DPython_EXECUTABLE={sys.executable}",
            f"-DHAIRLOD_PYTHON_OUTPUT_DIR={output_dir}",
            "-DHAIRLOD_BUILD_TESTS=OFF", "-DHAIRLOD_BUILD_BENCH=OFF",
        ]
        subprocess.run(configure, check=True)
        jobs = str(os.cpu_count() or 2)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_core", "-j", jobs], check=True)


setup(
    package_dir={"": "addon"},
    packages=find_packages("addon"),
    package_data={"hairlod": ["blender_manifest.toml", "blender/preview/shaders/*.glsl"]},
    ext_modules=[CMakeExtension("hairlod._core")],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
