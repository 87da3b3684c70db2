"""Run by a Blender 4.2+ in which scripts/build_addon.py's extension was installed with
`blender --command extension install-file -r user_default -e ZIP` (same BLENDER_USER_RESOURCES):
the headless pipeline an artist's CI would run, from the installed extension: write a USC .data hair
file, import it, build the LoD and export it with baked BCSDF tables.

    blender -b --python-exit-code 1 --python tests/packages/blender_extension.py -- HAIR_FILE OUT_DIR
"""

import importlib
import json
import os
import sys

import bpy

MODULE = "bl_ext.user_default.hairlod"


def main(hair_file, out_dir):
    enabled = {addon.module for addon in bpy.context.preferences.addons}
    assert MODULE in enabled, f"{MODULE} is not enabled (enabled: {sorted(enabled)})"
    hairlod = importlib.import_module(MODULE)
    pipeline = importlib.import_module(MODULE + ".blender.pipeline")
    core = os.path.realpath(hairlod._core.__file__)
    assert "hairlod_native" in core and bpy.utils.user_resource('EXTENSIONS') in core, core

    data_file = os.path.join(out_dir, "hair.data")
    hairlod.io.write(data_file, hairlod.io.read(hair_file))
    bpy.ops.wm.read_homefile(use_empty=True)
    assert bpy.ops.hairlod.import_hair(filepath=data_file) == {'FINISHED'}
    obj = bpy.context.active_object
    assert obj is not None and obj.type == 'CURVES', obj
    asset = pipeline.build_lod(obj, levels=4, control_points=8, seed=1)
    summary = pipeline.export_lod(obj, os.path.join(out_dir, "export"), theta_samples=16, hair_count_samples=8)
    baked = sorted(os.listdir(summary["bcsdf"]))
    assert any(name.endswith(".exr") for name in baked), baked
    assert os.path.isfile(os.path.join(summary["lod"], "manifest.json")), os.listdir(summary["lod"])
    print(f"extension in Blender {bpy.app.version_string}: core {os.path.basename(core)}, "
          f"{len(obj.data.curves)} strands -> {len(asset.levels)} levels, exported {json.dumps(summary['levels'])}, "
          f"baked {len(baked)} files")


main(*sys.argv[sys.argv.index("--") + 1:][:2])
