"""scripts/build_addon.py: the add-on zip (no Blender needed)."""

import importlib.util
import shutil
import zipfile

import pytest

from conftest import REPO

spec = importlib.util.spec_from_file_location("build_addon", REPO / "scripts" / "build_addon.py")
build_addon = importlib.util.module_from_spec(spec)
spec.loader.exec_module(build_addon)


@pytest.fixture
def package_copy(tmp_path, monkeypatch):
    """A copy of addon/hairlod that the build reads instead of the real one."""
    copy = tmp_path / "hairlod"
    shutil.copytree(REPO / "addon" / "hairlod", copy)
    monkeypatch.setattr(build_addon, "PACKAGE_DIR", str(copy))
    return copy


def test_zip_holds_the_package_without_caches(package_copy, tmp_path):
    (package_copy / "__pycache__").mkdir(exist_ok=True)
    (package_copy / "__pycache__" / "io.cpython-311.pyc").write_bytes(b"")
    (package_copy / "_core.cpython-39-x86_64-linux-gnu.so").write_bytes(b"other python")
    target = build_addon.build(str(tmp_path / "dist"))
    assert target.endswith(".zip") and "hairlod-0.1.0-linux-" in target
    names = zipfile.ZipFile(target).namelist()
    assert all(name.startswith("hairlod/") for name in names)
    assert {"hairlod/__init__.py", "hairlod/blender_manifest.toml", "hairlod/blender/curves.py",
            "hairlod/" + build_addon.CORE_NAME} <= set(names)
    assert not [name for name in names if "__pycache__" in name or "cpython-39" in name]
    assert [p.name for p in (tmp_path / "dist").iterdir()] == [target.rsplit("/", 1)[1]]


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
