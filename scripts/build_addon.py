#!/usr/bin/python3
"""Packs hairlod for Blender, for the Python running this script (the one the Blender embeds):

- dist/hairlod-<version>-cp3XY-linux_x64.zip: a Blender 4.2+ extension (blender_manifest.toml at its
  root; the compiled core in wheels/hairlod_native-<version>-cp3XY-cp3XY-linux_x86_64.whl);
- dist/hairlod-<version>-cp3XY-linux_x64-legacy.zip: the add-on for Blender 3.4-4.1 (Preferences >
  Add-ons > Install), one top-level hairlod/ folder with the core inside.

In both, the core is self-contained (scripts/native_bundle.py): the shared libraries it loads,
except the C/C++ runtime, travel with it under names of their own. Run `make build` first (for
cp313, inside the Debian 13 chroot: `make addon` does both). Usage:

    /usr/bin/python3 scripts/build_addon.py [--output-dir dist]
"""

import argparse
import ast
import base64
import hashlib
import os
import shutil
import sys
import sysconfig
import tempfile
import tomllib
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import native_bundle  # noqa: E402

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
PACKAGE_DIR = os.path.join(REPO_ROOT, "addon", "hairlod")
CORE_NAME = "_core" + sysconfig.get_config_var("EXT_SUFFIX")
PYTHON_TAG = f"cp{sys.version_info.major}{sys.version_info.minor}"
PLATFORM = "linux_x64"          # Blender's name for the platform (manifest, file names)
WHEEL_PLATFORM = "linux_x86_64"  # the wheel tag Blender maps to it
WHEEL_PACKAGE = "hairlod_native"  # hairlod/_native.py imports hairlod_native._core from the wheel
LIBS_DIR = "_core.libs"          # beside the core, in the legacy zip and in the wheel
# Fixed timestamps make the zips depend on the files' contents only.
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


def python_files():
    """(absolute path, path inside the package) of the package's files, without compiled cores or caches."""
    for directory, subdirectories, files in os.walk(PACKAGE_DIR):
        subdirectories[:] = sorted(d for d in subdirectories if d != "__pycache__" and not d.endswith(".libs"))
        for name in sorted(files):
            if name.endswith(".pyc") or name.startswith("_core"):
                continue
            path = os.path.join(directory, name)
            yield path, os.path.relpath(path, PACKAGE_DIR)


def bundled_core(staging):
    """The core and its libraries, made self-contained, in `staging`: [(path, relative name)]."""
    core = os.path.join(staging, CORE_NAME)
    shutil.copyfile(os.path.join(PACKAGE_DIR, CORE_NAME), core)
    libs = os.path.join(staging, LIBS_DIR)
    native_bundle.bundle(core, libs)
    native_bundle.check_self_contained(core, libs)
    return [(core, CORE_NAME)] + [(os.path.join(libs, name), f"{LIBS_DIR}/{name}") for name in sorted(os.listdir(libs))]


class _Zip:
    """A zip written under a temporary name beside `target` and renamed when complete."""

    def __init__(self, target):
        self.target = target
        handle, self.temporary = tempfile.mkstemp(suffix=".zip.tmp", dir=os.path.dirname(target))
        os.close(handle)
        self.archive = zipfile.ZipFile(self.temporary, "w", zipfile.ZIP_DEFLATED)

    def add(self, name, data, mode=0o644):
        info = zipfile.ZipInfo(name, ZIP_DATE_TIME)
        info.compress_type = zipfile.ZIP_DEFLATED
        info.external_attr = (mode & 0o777) << 16
        self.archive.writestr(info, data)

    def add_file(self, path, name):
        with open(path, "rb") as source:
            self.add(name, source.read(), os.stat(path).st_mode)

    def __enter__(self):
        return self

    def __exit__(self, kind, error, trace):
        self.archive.close()
        if kind is None:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(self.temporary, 0o666 & ~umask)  # mkstemp's 0600 -> a plain write's permissions
            os.replace(self.temporary, self.target)
        else:
            os.remove(self.temporary)


def wheel(core_files, version, output):
    """The hairlod_native wheel (PEP 427) holding the core; returns its file name."""
    tag = f"{PYTHON_TAG}-{PYTHON_TAG}-{WHEEL_PLATFORM}"
    name = f"{WHEEL_PACKAGE}-{version}-{tag}.whl"
    info = f"{WHEEL_PACKAGE}-{version}.dist-info"
    entries = [(f"{WHEEL_PACKAGE}/__init__.py",
                b'"""The compiled core of the hairlod Blender extension (loaded by hairlod/_native.py)."""\n', 0o644)]
    for path, relative in core_files:
        with open(path, "rb") as source:
            entries.append((f"{WHEEL_PACKAGE}/{relative}", source.read(), 0o755))
    entries.append((f"{info}/METADATA", f"Metadata-Version: 2.1\nName: {WHEEL_PACKAGE}\nVersion: {version}\n"
                    f"Summary: Compiled core of the hairlod Blender extension\n".encode(), 0o644))
    entries.append((f"{info}/WHEEL", f"Wheel-Version: 1.0\nGenerator: hairlod build_addon.py\nRoot-Is-Purelib: false\n"
                    f"Tag: {tag}\n".encode(), 0o644))
    record = "".join(f"{entry},sha256={_digest(data)},{len(data)}\n" for entry, data, _ in entries) + f"{info}/RECORD,,\n"
    entries.append((f"{info}/RECORD", record.encode(), 0o644))
    with _Zip(os.path.join(output, name)) as archive:
        for entry, data, mode in entries:
            archive.add(entry, data, mode)
    return name


def _digest(data):
    return base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def extension_manifest(wheel_name):
    """The package's manifest with the wheel listed (top-level keys go before the first table)."""
    with open(os.path.join(PACKAGE_DIR, "blender_manifest.toml"), encoding="utf-8") as manifest:
        text = manifest.read()
    head, table, tail = text.partition("\n[")
    return f'{head.rstrip()}\n\nwheels = ["./wheels/{wheel_name}"]\n{table}{tail}'


def build(output_dir):
    """Writes the extension and the legacy zip; returns their paths."""
    if not os.path.isfile(os.path.join(PACKAGE_DIR, CORE_NAME)):
        raise BuildError(f"addon/hairlod/{CORE_NAME} is missing: build the core first (make build)")
    version = bl_info_version()
    if manifest_version() != version:
        raise BuildError(f"blender_manifest.toml version {manifest_version()} differs from "
                         f"bl_info version {version}")
    os.makedirs(output_dir, exist_ok=True)
    extension = os.path.join(output_dir, f"hairlod-{version}-{PYTHON_TAG}-{PLATFORM}.zip")
    legacy = os.path.join(output_dir, f"hairlod-{version}-{PYTHON_TAG}-{PLATFORM}-legacy.zip")
    with tempfile.TemporaryDirectory(dir=output_dir, prefix=".build-") as staging:
        core_files = bundled_core(staging)
        wheel_name = wheel(core_files, version, staging)
        with _Zip(extension) as archive:
            for path, relative in python_files():
                if relative == "blender_manifest.toml":
                    archive.add(relative, extension_manifest(wheel_name).encode())
                else:
                    archive.add_file(path, relative)
            archive.add_file(os.path.join(staging, wheel_name), f"wheels/{wheel_name}")
        with _Zip(legacy) as archive:
            for path, relative in python_files():
                if relative != "blender_manifest.toml":  # 4.2+ would take a zip with one for an extension
                    archive.add_file(path, f"hairlod/{relative}")
            for path, relative in core_files:
                archive.add_file(path, f"hairlod/{relative}")
    return [extension, legacy]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", default=os.path.join(REPO_ROOT, "dist"),
                        help="folder for the zips (default: <repo>/dist)")
    args = parser.parse_args()
    try:
        for path in build(os.path.abspath(args.output_dir)):
            print(path)
    except (BuildError, native_bundle.BundleError, OSError) as error:
        print(f"build_addon.py: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
