"""The LoD preview follows the asset that Build Hair LoD packs into the hair object: it appears after
the build, after saving and reopening the .blend, and after disabling and re-enabling the add-on;
undoing the build takes it away (Blender under Xvfb, see scripts/run_ui_tests.sh)."""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check  # noqa: E402


REDRAW_DELAY = 1.0


def view3d_area():
    window = bpy.context.window_manager.windows[0]
    return window, next(a for a in window.screen.areas if a.type == 'VIEW_3D')


def drawn_segments(name):
    from hairlod.blender.preview import lod_preview

    obj = bpy.data.objects[name]
    preview = lod_preview.preview_of(obj)
    return None if preview is None else preview.stats.get("segments")


def steps():
    import addon_utils

    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    _, hair = harness.generated_hair_object(count=4000, vertices=9, seed=2)
    window, area = view3d_area()
    region = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_all()
        check(bpy.ops.hairlod.build_lod('EXEC_DEFAULT', guides=24, levels=4, control_points=8) == {'FINISHED'},
              "Build Hair LoD finished")
    area.tag_redraw()
    yield REDRAW_DELAY
    check((drawn_segments("Hair") or 0) > 0, f"the preview draws after the build ({drawn_segments('Hair')} segments)")

    path = os.path.join(os.environ.get("TMPDIR", "/tmp"), "lod_preview_persistence.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    yield REDRAW_DELAY
    window, area = view3d_area()
    area.tag_redraw()
    yield REDRAW_DELAY
    check((drawn_segments("Hair") or 0) > 0, "the preview draws after reopening the .blend")

    addon_utils.disable("hairlod", default_set=True)
    addon_utils.enable("hairlod", default_set=True)
    yield REDRAW_DELAY
    area.tag_redraw()
    yield REDRAW_DELAY
    check((drawn_segments("Hair") or 0) > 0, "the preview draws after disabling and re-enabling the add-on")

    del bpy.data.objects["Hair"]["hairlod_lod_asset"]
    area.tag_redraw()
    yield REDRAW_DELAY
    from hairlod.blender.preview import lod_preview

    check(lod_preview.preview_of(bpy.data.objects["Hair"]) is None, "removing the packed asset removes the preview")


harness.run(steps)
