"""Run by python3 in a bare Debian 12 (python3 and python3-numpy only, scripts/chroot.sh bare12) on a
zip made by scripts/build_addon.py: unpacks it as Blender would (the legacy add-on folder, or the
extension with its wheel in site-packages), imports hairlod, builds an LoD of a real hair file and
bakes its BCSDF tables, and checks that no library bundled with the core was loaded from elsewhere
(the chroot has none of them: TBB, Embree, OpenSubdiv, OpenEXR are not installed there).

    python3 tests/packages/bare_import.py ZIP legacy|extension HAIR_FILE
"""

import glob
import os
import sys
import tempfile
import zipfile


def unpack(archive, kind, folder):
    """Puts the package where Blender would and returns the sys.path entries that make it importable."""
    with zipfile.ZipFile(archive) as zipped:
        if kind == "legacy":
            zipped.extractall(os.path.join(folder, "addons"))
            return [os.path.join(folder, "addons")]
        zipped.extractall(os.path.join(folder, "extension", "hairlod"))
    site = os.path.join(folder, "site-packages")
    wheels = glob.glob(os.path.join(folder, "extension", "hairlod", "wheels", "*.whl"))
    assert len(wheels) == 1, wheels
    with zipfile.ZipFile(wheels[0]) as wheel:
        wheel.extractall(site)
    return [os.path.join(folder, "extension"), site]


def main(archive, kind, hair_file):
    with tempfile.TemporaryDirectory() as folder:
        sys.path[:0] = unpack(archive, kind, folder)
        import numpy as np

        import hairlod
        from hairlod import bcsdf, bcsdf_bake, hair_params, lod

        core = os.path.realpath(hairlod._core.__file__)
        assert core.startswith(os.path.realpath(folder)), core
        strands = hairlod.io.read(hair_file)
        asset = lod.build_lod(strands, levels=4, control_points=8, seed=1)
        bake_dir = os.path.join(folder, "bake")
        crossed, _ = bcsdf.lod_hair_count_range(asset)
        bcsdf_bake.bake(hair_params.as_params(), bake_dir,
                   theta_samples=16, hair_count_samples=8, max_hair_count=max(crossed, 1.0 + 1e-6))
        baked = sorted(os.listdir(bake_dir))
        assert any(name.endswith(".exr") for name in baked), baked
        with open("/proc/self/maps") as maps:
            loaded = {line.split()[-1] for line in maps if ".so" in line.split()[-1]}
        libs = os.path.join(os.path.dirname(core), "_core.libs")
        bundled = {name.partition("-hairlod-")[0] for name in os.listdir(libs)}
        ours = {path for path in loaded if os.path.realpath(path).startswith(os.path.realpath(libs))}
        assert len(ours) == len(bundled), f"bundled {sorted(bundled)}, loaded {sorted(ours)}"
        # The same libraries (libtbb.so.12, ...) loaded from the system would mean the bundle leaks
        # (but for zlib, which Python's own zlib module loads from the system).
        elsewhere = sorted(path for path in loaded - ours if os.path.basename(path).partition(".so")[0] in bundled
                           and os.path.basename(path).partition(".so")[0] != "libz")
        assert not elsewhere, f"bundled libraries also loaded from the system: {elsewhere}"
        print(f"bare {kind}: imported {os.path.relpath(core, folder)}, {strands.curve_count} "
              f"strands -> {len(asset.levels)} levels, baked {len(baked)} files; "
              f"{len(ours)} libraries from the package, NumPy {np.__version__}")


if __name__ == "__main__":
    main(*sys.argv[1:4])
