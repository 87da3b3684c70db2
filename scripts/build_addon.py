#!/usr/bin/python3
"""Packs the Blender add-on: dist/hairlod-<version>-<platform>.zip with one top-level hairlod/ folder.

The zip installs through Preferences > Add-ons > Install (Blender 3.4+) and, with its
blender_manifest.toml, as an extension (Blender 4.2+). It holds the compiled core for this
Python (the one Blender embeds), so run `make build` first. Usage:

    /usr/bin/python3 scripts/build_addon.py [--output-dir dist]
"""

import argparse
import ast
import os
import platform
import sys
import sysconfig
import tempfile
import tomllib
import zipfile

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
PACKAGE_DIR = os.path.join(REPO_ROOT, "addon", "hairlod")
CORE_NAME = "_core" + sysconfig.get_config_var("EXT_SUFFIX")
# Fixed timestamps make the zip depend on the files' contents only.
ZIP_DATE_TIME = (2024, 1, 1, 0, 0, 0)


class BuildError(Exception):
    pass


def bl_info_version():
    """bl_info["version"] as "x.y.z", read without importing the package (which needs the compiled core)."""
    with open(os.path.join(PACKAGE_DIR, "__init__.py"), encoding="utf-8") as source:
        tree = ast.parse(source.read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "bl_info" for t in node.targets):
            return ".".join(str(part) for part in ast.literal_eval(node.value)["version"])
    raise BuildError("addon/hairlod/__init__.py has no bl_info")


def manifest_version():
    with open(os.path.join(PACKAGE_DIR, "blender_manifest.toml"), "rb") as manifest:
        return tomllib.load(manifest)["version"]


def package_files():
    """(absolute path, path inside the zip) of every file the add-on ships."""
    for directory, subdirectories, files in os.walk(PACKAGE_DIR):
        subdirectories[:] = sorted(d for d in subdirectories if d != "__pycache__")
        for name in sorted(files):
            # Cores built for other Pythons would not load in Blender's.
            if name.endswith(".pyc") or (name.startswith("_core") and name != CORE_NAME):
                continue
            path = os.path.join(directory, name)
            yield path, os.path.join("hairlod", os.path.relpath(path, PACKAGE_DIR))


def build(output_dir):
    if not os.path.isfile(os.path.join(PACKAGE_DIR, CORE_NAME)):
        raise BuildError(f"addon/hairlod/{CORE_NAME} is missing: build the core first (make build)")
    version = bl_info_version()
    if manifest_version() != version:
        raise BuildError(f"blender_manifest.toml version {manifest_version()} differs from "
                         f"bl_info version {version}")
    target = os.path.join(output_dir, f"hairlod-{version}-{sys.platform}-{platform.machine()}.zip")
    os.makedirs(output_dir, exist_ok=True)
    # Written next to the target and renamed when complete: no partial zip is ever left.
    handle, temporary = tempfile.mkstemp(suffix=".zip.tmp", dir=output_dir)
    os.close(handle)
    try:
        with zipfile.ZipFile(temporary, "w", zipfile.ZIP_DEFLATED) as archive:
            for path, name in package_files():
                info = zipfile.ZipInfo(name, ZIP_DATE_TIME)
                info.compress_type = zipfile.ZIP_DEFLATED
                info.external_attr = (os.stat(path).st_mode & 0o777) << 16
                with open(path, "rb") as source:
                    archive.writestr(info, source.read())
        os.replace(temporary, target)
    except BaseException:
        os.remove(temporary)
        raise
    return target


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", default=os.path.join(REPO_ROOT, "dist"),
                        help="folder for the zip (default: <repo>/dist)")
    args = parser.parse_args()
    try:
        print(build(os.path.abspath(args.output_dir)))
    except (BuildError, OSError) as error:
        print(f"build_addon.py: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
