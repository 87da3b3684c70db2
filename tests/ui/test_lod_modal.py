"""Build Hair LoD runs modal in a real window (Blender under Xvfb, see scripts/run_ui_tests.sh).

Invokes the operator as a click would, in a viewport at rest: it must return RUNNING_MODAL, report
progress from its timer, leave the viewport undrawn until the build is done (a change would make
Blender redraw it once per sample of its anti-aliasing, taking the CPU from the build), and finish
with one Curves object per level and the packed asset. Invoked again and sent Esc
(simulated) while it builds, it must leave no object, hair data or collection behind. Exits 0 on
success, 1 on failure.
"""

import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "blender"))
sys.path.insert(0, os.path.join(harness.REPO_ROOT, "scripts"))
from viewport_capture import RedrawTimes  # noqa: E402  (scripts/viewport_capture.py)

POLL_DELAY = 0.2
QUIET = 2.0  # seconds without a redraw: the viewport is at rest
TIMEOUT = 120.0


def counts():
    return len(bpy.data.objects), len(bpy.data.hair_curves), len(bpy.data.collections)


def steps():
    import addon_utils

    from hairlod.blender.curves import strands_to_curves
    from hairlod.blender.lod_build_job import COLLECTION_NAME
    from hairlod.blender.lod_operator import HAIRLOD_OT_build_lod
    from hairlod.blender.packed_asset import PACKED_PROPERTY, packed_asset
    from hair_fixtures import hanging_hair  # tests/blender/hair_fixtures.py

    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    source = strands_to_curves(hanging_hair(40000, points=12), "Hair")
    bpy.context.view_layer.objects.active = source
    progress, escapes = [], []
    modal = HAIRLOD_OT_build_lod.modal

    built = []  # when a timer event first found the build thread done (the level objects are made after)

    def recording_modal(operator, context, event):
        if event.type == 'TIMER':
            progress.append(operator._job.fraction)
            if not built and not operator._job._thread.is_alive():
                built.append(time.perf_counter())
        result = modal(operator, context, event)
        if event.type == 'ESC':
            escapes.append((operator._job.fraction, result))
        return result

    HAIRLOD_OT_build_lod.modal = recording_modal
    region_draws = RedrawTimes()
    area.tag_redraw()
    yield from region_draws.at_rest(QUIET)  # as when an artist presses the button
    before = counts()
    invoked = time.perf_counter()
    with bpy.context.temp_override(window=window, area=area):
        started = bpy.ops.hairlod.build_lod('INVOKE_DEFAULT', guides=32, levels=5, control_points=8, level_objects=True)
    check(started == {'RUNNING_MODAL'}, f"the operator runs modal ({started})")
    deadline = time.monotonic() + TIMEOUT
    while PACKED_PROPERTY not in source and time.monotonic() < deadline:
        yield POLL_DELAY
    region_draws.remove()
    check(PACKED_PROPERTY in source and built, "the build finished and packed the asset")
    during = [t for t in region_draws if invoked < t < built[0]]
    check(not during, f"the viewport was not redrawn while the build ran ({len(during)} redraws in "
                      f"{built[0] - invoked:.2f} s)")
    check(len(progress) >= 3 and progress == sorted(progress), f"progress rose over {len(progress)} timer events")
    levels, thick_levels = len(bpy.data.collections[COLLECTION_NAME].objects), len(packed_asset(source).levels)
    # levels=5 is the most; the hierarchy stops where the area no longer shrinks about 4x.
    check(levels == thick_levels and 2 <= levels <= 4, f"one Curves object per thick level ({levels}, {thick_levels})")
    made = list(bpy.data.collections[COLLECTION_NAME].objects)
    check(all(obj.hide_get() and obj.hide_render for obj in made), "the level objects are hidden and not rendered")
    check(source.display_type == 'BOUNDS' and source.hairlod_lod_preview.enabled,
          "the preview replaces the source's drawing (it draws as its bounds)")
    source.hairlod_lod_preview.enabled = False
    check(source.display_type == 'TEXTURED', f"the preview toggle restores the source's display ({source.display_type})")
    source.hairlod_lod_preview.enabled = True
    after = counts()

    del source[PACKED_PROPERTY]
    progress.clear()
    with bpy.context.temp_override(window=window, area=area):
        # Level objects: one more timer step per level, so that Esc comes while the build still runs.
        started = bpy.ops.hairlod.build_lod('INVOKE_DEFAULT', guides=32, levels=5, control_points=8, level_objects=True)
    check(started == {'RUNNING_MODAL'}, "invoked again")
    yield POLL_DELAY
    window.event_simulate('ESC', 'PRESS')
    yield POLL_DELAY
    check(len(escapes) == 1 and escapes[0][1] == {'CANCELLED'} and escapes[0][0] < 1,
          f"Esc reached the running operator and cancelled it ({escapes})")
    timer_events = len(progress)
    yield 2.0  # longer than the whole build: a build that went on would have finished by now
    HAIRLOD_OT_build_lod.modal = modal
    check(len(progress) == timer_events, "no timer events after the cancel")
    check(PACKED_PROPERTY not in source, "Esc stopped the build before it packed an asset")
    check(counts() == after, f"Esc left nothing behind ({counts()} vs {after})")
    check(after[0] == before[0] + levels, "the first build's objects are still there")


harness.run(steps)
