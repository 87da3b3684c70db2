"""examples/convert_blend_to_lod.py, run as CI would: headless Blender over a .blend with two hair
Curves objects (one with a Principled Hair BSDF material), exporting an LoD folder and baked tables
for each."""

import json
import os
import subprocess
import textwrap

import pytest

import hairlod
from hairlod import lod

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))

# 3000 strands a object: with the test's 16 guides and 4 levels they split into 3 thick levels. At 1500
# the top level's hairs of about 33 strands split barely 3x in area and may leave one thick level.
MAKE_BLEND = textwrap.dedent("""
    import sys
    sys.path.insert(0, {addon!r})
    import bpy
    import addon_utils
    addon_utils.enable("hairlod", default_set=True)
    import hairlod
    from hairlod import hairmesh
    from hairlod.blender.curves import strands_to_curves
    from hairlod.blender.principled_hair import new_hair_material
    bpy.ops.wm.read_homefile(use_empty=True)
    source = hairmesh.read({hair_mesh!r})
    for name, seed in (("Bob", 1), ("Fringe", 2)):
        obj = strands_to_curves(hairlod.generate_strands(source, count=3000, vertices=9, seed=seed), name)
    material = new_hair_material("Auburn", {{"parametrization": 'MELANIN', "melanin": 0.6}})
    bpy.data.objects["Bob"].data.materials.append(material)
    bpy.ops.wm.save_as_mainfile(filepath={blend!r})
""")


def run_blender(blender, *arguments):
    env = {**os.environ, "TMPDIR": os.environ.get("TMPDIR", "/tmp")}
    return subprocess.run([blender, "-b", "--factory-startup", *arguments], capture_output=True, text=True, env=env,
                          timeout=600)


def test_every_curves_object_is_converted_and_exported(tmp_path, blender):
    blend = str(tmp_path / "hair.blend")
    script = MAKE_BLEND.format(addon=os.path.join(REPO_ROOT, "addon"), blend=blend,
                               hair_mesh=os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json"))
    made = run_blender(blender, "--python-exit-code", "1", "--python-expr", script)
    assert made.returncode == 0 and os.path.isfile(blend), made.stderr[-2000:]

    out = tmp_path / "out"
    run = run_blender(blender, blend, "--python-exit-code", "1", "--python",
                      os.path.join(REPO_ROOT, "examples", "convert_blend_to_lod.py"), "--", "--out", str(out),
                      "--guides", "16", "--levels", "4", "--control-points", "8", "--save")
    assert run.returncode == 0, run.stderr[-2000:]
    result = json.loads(next(line for line in run.stdout.splitlines() if line.startswith("{")))
    assert result["failed"] == []
    by_name = {entry["object"]: entry for entry in result["objects"]}
    assert set(by_name) == {"Bob", "Fringe"}
    assert by_name["Bob"]["material"] == "Principled Hair BSDF" and by_name["Fringe"]["material"] == "LoD preview panel"
    for name in ("Bob", "Fringe"):
        asset = lod.load(out / name / "lod")
        assert asset.strand_count == 3000
        assert len(asset.levels) == len(by_name[name]["levels"]) >= 2
        for position in range(len(asset.levels)):
            hairs = hairlod.io.read(str(out / name / "lod" / f"level{position}.hair"))
            assert len(hairs) == len(asset.levels[position].n_total)
        manifest = json.loads((out / name / "bcsdf" / "manifest.json").read_text())
        assert {t["name"] for t in manifest["tables"]} >= {"fiber_attenuation", "dual_scattering",
                                                           "aggregated_attenuation"}
    # Different materials bake different tables.
    bob = json.loads((out / "Bob" / "bcsdf" / "manifest.json").read_text())["params"]
    fringe = json.loads((out / "Fringe" / "bcsdf" / "manifest.json").read_text())["params"]
    assert bob["sigma_a"] != fringe["sigma_a"]


def test_bad_arguments_exit_2(tmp_path, blender):
    run = run_blender(blender, "--python-exit-code", "1", "--python", os.path.join(REPO_ROOT, "examples", "convert_blend_to_lod.py"),
                      "--", "--guides", "8")
    assert run.returncode == 2 and "--out" in run.stderr
