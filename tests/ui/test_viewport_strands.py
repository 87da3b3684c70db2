"""Viewport Strands of a hair mesh are drawn in a real viewport (Blender under Xvfb, see
scripts/run_ui_tests.sh).

Builds a hair mesh on the upper half of a sphere, frames it, and screenshots the window with the
hair mesh's Viewport Strands off and on: the strands must change a good share of the viewport's
pixels, only inside the viewport, in the hair colours (red above blue). Zooming out must lower the
level of detail (Bhokare 2024 Eq. 7) and draw fewer strands; with a near and a far view open, the near one sets
the level and redraws regenerate nothing. Screenshots go to $HAIRLOD_UI_OUT (default
<repo>/out/ui). Exits 0 on success, 1 on failure.
"""

import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check, crop  # noqa: E402

REDRAW_DELAY = 1.0


def view3d(window):
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    return area, next(r for r in area.regions if r.type == 'WINDOW')


def screenshot(window, area, name):
    return harness.screenshot(window, area, name, whole_window=True)



def steps():
    import addon_utils

    window = bpy.context.window_manager.windows[0]
    area, region = view3d(window)
    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    from hairlod.blender.hair_mesh_gpu_preview import preview_state

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0)
    sphere = bpy.context.active_object
    centres = np.empty((len(sphere.data.polygons), 3), np.float32)
    sphere.data.polygons.foreach_get("center", centres.ravel())
    sphere.data.polygons.foreach_set("select", centres[:, 2] > 0.2)
    check(bpy.ops.hairlod.hair_mesh_from_faces(layers=3, length=0.8, taper=0.0) == {'FINISHED'}, "hair mesh made")
    hair = bpy.context.active_object
    sphere.hide_set(True)
    settings = hair.hairlod_strands
    settings.count, settings.vertices, settings.curl_radius, settings.curl_frequency = 20000, "17", 0.03, 4.0
    space = area.spaces.active
    space.shading.type = 'SOLID'
    space.overlay.show_overlays = False  # grid and outlines would differ little, but keep the diff clean
    space.region_3d.view_perspective = 'PERSP'
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_axis(type='FRONT')
        bpy.ops.view3d.view_selected()
    hair.display_type = 'WIRE'  # the cage's faces would hide the strands inside it
    yield REDRAW_DELAY

    without = screenshot(window, area, "viewport_strands_off.png")
    settings.viewport_strands = True
    area.tag_redraw()
    yield REDRAW_DELAY
    yield REDRAW_DELAY
    with_strands = screenshot(window, area, "viewport_strands_on.png")
    state = preview_state(hair)
    check(state is not None and state.error is None, f"preview state without error ({state and state.error})")
    near_count = state.batch.strand_count
    check(near_count > 0.9 * settings.count, f"full detail near the camera ({near_count} strands, LoD {state.level})")
    print(f"update: generate {state.timings['generate_s'] * 1e3:.1f} ms, buffers {state.timings['upload_s'] * 1e3:.1f} ms"
          f" for {near_count} strands")

    changed = np.abs(with_strands - without).max(axis=2) > 0.05
    in_view = crop(changed, window, region)
    check(in_view.mean() > 0.02, f"the strands change the viewport ({in_view.mean():.1%} of its pixels)")
    check(changed.sum() - in_view.sum() < 0.01 * in_view.sum(), "and nothing outside it")
    strand_pixels = crop(with_strands, window, region)[in_view]
    check(np.median(strand_pixels[:, 0] - strand_pixels[:, 2]) > 0.02,
          "changed pixels have the hair ramp's colour (red above blue)")

    # Zooming out: the hair mesh spans fewer pixels, so Bhokare 2024 Eq. 7 lowers the level and fewer strands are drawn.
    space.region_3d.view_distance *= 12.0
    area.tag_redraw()
    yield REDRAW_DELAY
    far = preview_state(hair)
    check(far.level < 0.5 and far.batch.strand_count < 0.6 * near_count,
          f"zoomed out: LoD {far.level:.2f}, {far.batch.strand_count} strands (near: {near_count})")
    far_pixels = screenshot(window, area, "viewport_strands_far.png")
    check(np.abs(far_pixels - without).max() > 0.05, "the far strands are still drawn")

    settings.viewport_strands = False
    area.tag_redraw()
    space.region_3d.view_distance /= 12.0
    yield REDRAW_DELAY
    off_again = screenshot(window, area, "viewport_strands_off_again.png")
    check((np.abs(off_again - without).max(axis=2) > 0.05).mean() < 0.001, "turning it off removes the strands")

    # Two 3D views, one near and one far: the nearest sets the level of the strands both draw, and
    # redrawing either one must not regenerate (no views taking turns).
    with bpy.context.temp_override(window=window, area=area, region=region):
        check(bpy.ops.screen.area_split(direction='VERTICAL', factor=0.5) == {'FINISHED'}, "viewport split in two")
    views = [a for a in window.screen.areas if a.type == 'VIEW_3D']
    check(len(views) == 2, f"two 3D views ({len(views)})")
    views[1].spaces.active.region_3d.view_distance = 12.0 * views[0].spaces.active.region_3d.view_distance
    settings.viewport_strands = True
    for view in views:
        view.tag_redraw()
    yield REDRAW_DELAY
    two = preview_state(hair)
    drawn = list(two.batch.batches)
    from hairlod.blender.hair_mesh_gpu_preview import camera_detail_level, quantised_level, world_bounds

    def level_of(view):
        region_3d, view_region = view.spaces.active.region_3d, next(r for r in view.regions if r.type == 'WINDOW')
        return quantised_level(camera_detail_level(world_bounds(hair), region_3d.view_matrix, region_3d.window_matrix,
                                                   region_3d.is_perspective, view_region.height,
                                                   settings.full_detail_px))

    near_level, far_level = level_of(views[0]), level_of(views[1])
    check(far_level < near_level and two.level == near_level,
          f"the near view sets the level with a far one open: LoD {two.level} (near {near_level}, far {far_level})")
    for _ in range(2):
        for view in reversed(views):
            view.tag_redraw()
        yield REDRAW_DELAY
    check(all(a is b for a, b in zip(preview_state(hair).batch.batches, drawn)) and len(drawn) > 0,
          "redrawing both views regenerates nothing")
    screenshot(window, area, "viewport_strands_two_views.png")


harness.run(steps, first_delay=REDRAW_DELAY)
