"""The Hair LoD sidebar tab is drawn in a real viewport (Blender under Xvfb, see scripts/run_ui_tests.sh).

Enables the add-on, imports a hair file, opens the sidebar on the "Hair LoD" tab and takes a
screenshot; disables the add-on and takes another. The tab's panel must change the sidebar's
pixels, and only there. Then, the add-on enabled again: the panel draws Build Hair LoD's parameters
from the object's settings; the build button (the operator invoked with no parameters, as the panel
does) builds with the values set there, keeps them in its redo panel, and undo removes the build. Screenshots go to $HAIRLOD_UI_OUT (default <repo>/out/ui). Exits 0 on
success, 1 on failure.
"""

import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import REPO_ROOT, check, crop  # noqa: E402

# The bundled default input: the UI test needs no data from outside the repository.
BUNDLED_HAIR = os.path.join(REPO_ROOT, "examples", "data", "bob.hair")

# Seconds between steps: long enough for the window to redraw after each change.
REDRAW_DELAY = 1.0


def view3d_area_and_sidebar(window):
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    return area, next(r for r in area.regions if r.type == 'UI')


def screenshot(window, area, name):
    return harness.screenshot(window, area, name, whole_window=True)


POLL_DELAY = 0.2
BUILD_TIMEOUT = 120.0


class RecordingLayout:
    """Stands in for a UILayout: records (data, property) of every prop() drawn through it."""

    def __init__(self, drawn):
        self.drawn = drawn

    def prop(self, data, name, **_):
        self.drawn.append((data, name))

    def __getattr__(self, name):  # row(), column(), box(), label(), operator(): more of the same
        return lambda *args, **kwargs: self


def drawn_properties(context):
    drawn = []
    panel = type("Panel", (), {"layout": RecordingLayout(drawn)})()
    bpy.types.VIEW3D_PT_hairlod.draw(panel, context)
    return drawn


def build_from_the_panel(window, area):
    """The panel's parameters reach the build; redo keeps them; undo removes the build."""
    from hairlod.blender.lod_build_settings import BUILD_PROPERTIES
    from hairlod.blender.packed_asset import PACKED_PROPERTY, packed_asset

    obj = bpy.context.view_layer.objects.active
    check(obj is not None and obj.type == 'CURVES', "the imported hair is the active object")
    settings = obj.hairlod_lod_build
    drawn = drawn_properties(bpy.context)
    check(all((settings, name) in drawn for name in BUILD_PROPERTIES),
          f"the panel draws every build parameter from the object's settings ({len(drawn)} properties)")
    settings.guides, settings.levels, settings.control_points, settings.seed = 24, 3, 8, 5
    with bpy.context.temp_override(window=window, area=area):
        # The state undo must return to (the import, run from a timer, may share the initial undo step).
        bpy.ops.ed.undo_push(message="before the build")
        started = bpy.ops.hairlod.build_lod('INVOKE_DEFAULT')
    check(started == {'RUNNING_MODAL'}, "the build button starts the modal build")
    deadline = time.monotonic() + BUILD_TIMEOUT
    while PACKED_PROPERTY not in obj and time.monotonic() < deadline:
        yield POLL_DELAY
    yield REDRAW_DELAY
    asset = packed_asset(obj)
    check(asset is not None and (asset.guide_count, len(asset.levels) + 1, asset.control_points) == (24, 3, 8),
          "the build used the panel's guides, levels and control points")
    last = bpy.context.window_manager.operators[-1]
    check(last.bl_idname == "HAIRLOD_OT_build_lod" and
          all(getattr(last.properties, name) == getattr(settings, name) for name in BUILD_PROPERTIES),
          "the redo panel holds the parameters the build used")
    # The preview replaces the hair's own drawing; the sidebar shows its settings (looked at: nothing cut
    # at the default sidebar width).
    check(obj.display_type == 'BOUNDS', f"the built hair draws as its bounds under the preview ({obj.display_type})")
    screenshot(window, area, "sidebar_after_build.png")
    name = obj.name
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.ed.undo()
    yield REDRAW_DELAY
    check(PACKED_PROPERTY not in bpy.data.objects[name], "undo removes the build")
    check(bpy.data.objects[name].display_type == 'TEXTURED', "and gives the hair its own drawing back")


def steps():
    """Yields the delay before the next step; the timer callback drives it."""
    import addon_utils

    window = bpy.context.window_manager.windows[0]
    area, sidebar = view3d_area_and_sidebar(window)

    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    hair_file = BUNDLED_HAIR
    check(os.path.isfile(hair_file), f"test data present: {hair_file}")
    with bpy.context.temp_override(window=window, area=area):
        check(bpy.ops.hairlod.import_hair(filepath=hair_file) == {'FINISHED'}, "hair file imported")
    area.spaces.active.show_region_ui = True
    yield REDRAW_DELAY

    # Blender 3.4 has no Python access to the active sidebar tab: record when the panel draws
    # and cycle the tabs with Ctrl+Wheel over the empty bottom of the tab strip at the sidebar's
    # right edge, where no button takes the wheel (needs --enable-event-simulate).
    panel_draws = []
    draw = bpy.types.VIEW3D_PT_hairlod.draw

    def recording_draw(panel, context):
        draw(panel, context)
        panel_draws.append(context.region.as_pointer())  # only draws that did not raise

    bpy.types.VIEW3D_PT_hairlod.draw = recording_draw
    for _ in range(8):
        area, sidebar = view3d_area_and_sidebar(window)
        if sidebar.as_pointer() in panel_draws:
            break
        tab_strip_x, tab_strip_y = sidebar.x + sidebar.width - 8, sidebar.y + 16
        window.event_simulate('MOUSEMOVE', 'NOTHING', x=tab_strip_x, y=tab_strip_y)
        window.event_simulate('WHEELDOWNMOUSE', 'PRESS', ctrl=True, x=tab_strip_x, y=tab_strip_y)
        panel_draws.clear()
        yield REDRAW_DELAY
    bpy.types.VIEW3D_PT_hairlod.draw = draw
    check(sidebar.as_pointer() in panel_draws, "sidebar shows the Hair LoD tab")
    check(sidebar.width > 100 and sidebar.height > 100, f"sidebar is open ({sidebar.width}x{sidebar.height})")
    with_panel = screenshot(window, area, "sidebar_hairlod.png")
    addon_utils.disable("hairlod", default_set=True)
    area.tag_redraw()
    yield REDRAW_DELAY

    without_panel = screenshot(window, area, "sidebar_without_hairlod.png")
    check(with_panel.shape == without_panel.shape, "screenshots have the same size")
    changed = np.abs(with_panel - without_panel).max(axis=2) > 0.05
    in_sidebar = crop(changed, window, sidebar)
    check(in_sidebar.mean() > 0.01, f"the panel changes the sidebar ({in_sidebar.mean():.1%} of its pixels)")
    check(changed.sum() - in_sidebar.sum() < 0.1 * in_sidebar.sum(),
          f"and little else ({changed.sum() - in_sidebar.sum()} pixels outside it)")
    # Text and icons: the panel draws bright pixels on a darker background.
    panel = crop(with_panel, window, sidebar)
    check((panel.mean(axis=2) > 0.7).mean() > 0.002, "the panel shows text")

    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled again")
    yield from build_from_the_panel(window, area)


harness.run(steps)
