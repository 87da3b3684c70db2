"""scripts/build_addon.py: the Blender 4.2+ extension and the legacy add-on zip (no Blender needed;
tests/packages/ installs them in a bare Debian and in Blender 4.3)."""

import importlib.util
import shutil
import subprocess
import tomllib
import zipfile

import pytest

from conftest import REPO

spec = importlib.util.spec_from_file_location("build_addon", REPO / "scripts" / "build_addon.py")
build_addon = importlib.util.module_from_spec(spec)
spec.loader.exec_module(build_addon)

pytestmark = pytest.mark.skipif(shutil.which("patchelf") is None, reason="patchelf is not installed (make bootstrap)")


@pytest.fixture
def package_copy(tmp_path, monkeypatch):
    """A copy of addon/hairlod that the build reads instead of the real one."""
    copy = tmp_path / "hairlod"
    shutil.copytree(REPO / "addon" / "hairlod", copy)
    monkeypatch.setattr(build_addon, "PACKAGE_DIR", str(copy))
    return copy


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The two zips of the real package."""
    output = tmp_path_factory.mktemp("dist")
    extension, legacy = build_addon.build(str(output))
    return output, extension, legacy


def needed(data, tmp_path):
    path = tmp_path / "object.so"
    path.write_bytes(data)
    return subprocess.run(["patchelf", "--print-needed", str(path)], capture_output=True, text=True, check=True).stdout.split()


def test_names_carry_the_python_and_platform(built):
    output, extension, legacy = built
    tag = build_addon.PYTHON_TAG
    assert extension.endswith(f"hairlod-0.1.0-{tag}-linux_x64.zip")
    assert legacy.endswith(f"hairlod-0.1.0-{tag}-linux_x64-legacy.zip")
    assert sorted(p.name for p in output.iterdir()) == sorted([extension.rsplit("/", 1)[1], legacy.rsplit("/", 1)[1]])


def test_extension_lists_its_wheel_and_the_wheel_holds_a_self_contained_core(built, tmp_path):
    _, extension, _ = built
    with zipfile.ZipFile(extension) as archive:
        names = set(archive.namelist())
        manifest = tomllib.loads(archive.read("blender_manifest.toml").decode())
        assert {"__init__.py", "blender/curves.py", "blender_manifest.toml"} <= names
        assert not [n for n in names if n.startswith("_core") or "__pycache__" in n]
        assert manifest["platforms"] == ["linux-x64"] and len(manifest["wheels"]) == 1
        wheel_name = manifest["wheels"][0].removeprefix("./")
        assert wheel_name in names and wheel_name.endswith(f"{build_addon.PYTHON_TAG}-linux_x86_64.whl")
        (tmp_path / "w.whl").write_bytes(archive.read(wheel_name))
    with zipfile.ZipFile(tmp_path / "w.whl") as wheel:
        files = set(wheel.namelist())
        info = wheel_name.rsplit("/", 1)[1].split("-")[0] + "-0.1.0.dist-info"
        assert {f"{info}/WHEEL", f"{info}/METADATA", f"{info}/RECORD"} <= files
        record = wheel.read(f"{info}/RECORD").decode().splitlines()
        assert sorted(line.split(",")[0] for line in record) == sorted(files)
        core = f"hairlod_native/{build_addon.CORE_NAME}"
        libs = {f.rsplit("/", 1)[1] for f in files if f.startswith("hairlod_native/_core.libs/")}
        assert any(name.startswith("libembree") for name in libs) and any(name.startswith("libtbb") for name in libs)
        assert all("-hairlod-" in name for name in libs)
        for member in [core] + [f"hairlod_native/_core.libs/{name}" for name in libs]:
            for dependency in needed(wheel.read(member), tmp_path):
                assert dependency in libs or build_addon.native_bundle.RUNTIME.match(dependency), (member, dependency)


def test_legacy_zip_holds_the_package_without_manifest_or_caches(built):
    _, _, legacy = built
    names = zipfile.ZipFile(legacy).namelist()
    assert all(name.startswith("hairlod/") for name in names)
    assert {"hairlod/__init__.py", "hairlod/blender/curves.py", "hairlod/" + build_addon.CORE_NAME} <= set(names)
    assert "hairlod/blender_manifest.toml" not in names  # Blender 4.2+ would take it for an extension
    assert any(name.startswith("hairlod/_core.libs/libembree") for name in names)
    assert not [name for name in names if "__pycache__" in name]


def test_cores_for_other_pythons_stay_out(package_copy, tmp_path):
    (package_copy / "_core.cpython-39-x86_64-linux-gnu.so").write_bytes(b"other python")
    for target in build_addon.build(str(tmp_path / "dist")):
        assert not [n for n in zipfile.ZipFile(target).namelist() if "cpython-39" in n]


def test_missing_core_fails_clearly(package_copy, tmp_path):
    (package_copy / build_addon.CORE_NAME).unlink()
    with pytest.raises(build_addon.BuildError, match="make build"):
        build_addon.build(str(tmp_path / "dist"))
    assert not (tmp_path / "dist").exists()


def test_manifest_and_bl_info_versions_must_agree(package_copy, tmp_path):
    manifest = package_copy / "blender_manifest.toml"
    manifest.write_text(manifest.read_text().replace('version = "0.1.0"', 'version = "9.9.9"'))
    with pytest.raises(build_addon.BuildError, match="9.9.9"):
        build_addon.build(str(tmp_path / "dist"))
