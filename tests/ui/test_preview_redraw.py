"""The LoD preview draws the hair again only when what it shows changed, and averages the samples of
the viewport's anti-aliasing (Blender under Xvfb, see scripts/run_ui_tests.sh).

Blender redraws a viewport at rest once per sample of its anti-aliasing (Preferences > Viewport >
Anti-Aliasing, 8 samples by default). The preview draws the hair in the first of those redraws at the
pixels' centres and in each of the others once more, moved within the pixel, and shows their mean:
anti-aliased hair, whose pixels average the strands crossing them as a render's do. Once it holds as
many samples as the setting, it composites them again. Checked on 6,000 generated strands with the
preview on:
- after one change of the view, the hair is drawn once per redraw, 8 samples in all, and the layer
  then covers pixels partly (with one sample each pixel is hair or not); the light the hair adds to the
  picture stays within 5 % of one sample's; a redraw of the unchanged view draws no hair and gives the
  same pixels;
- with No Anti-Aliasing, one change of the view draws the hair once, in one sample;
- a change of each input draws the hair again, with different pixels where the input changes what
  the hair looks like: the light's strength, the world's colour, a preview setting, the material, the
  view, the hair's object transform;
- LodPreview.draw_again makes the next redraw draw the hair in full (what the benchmarks time).
Screenshots go to $HAIRLOD_UI_OUT (default out/ui).
"""

import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import REPO_ROOT, check, screenshot  # noqa: E402

sys.path.insert(0, os.path.join(REPO_ROOT, "scripts"))
from viewport_capture import RedrawTimes  # noqa: E402  (scripts/viewport_capture.py)

REDRAW_DELAY = 1.0
QUIET = 2.0  # seconds without a redraw: the viewport is at rest


def steps():
    import addon_utils

    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    from hairlod.blender.preview import lod_preview

    window = bpy.context.window_manager.windows[0]
    area, region_3d = harness.plain_view(next(a for a in window.screen.areas if a.type == 'VIEW_3D'))
    strands, hair = harness.generated_hair_object(count=6000, vertices=9, seed=3)
    light = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    bpy.context.scene.collection.objects.link(light)
    light.rotation_euler = (0.6, 0.2, 0.4)
    lower, upper = strands.points.min(axis=0), strands.points.max(axis=0)
    region_3d.view_location = 0.5 * (lower + upper)
    region_3d.view_distance = 1.6 * float(np.linalg.norm(upper - lower))
    with bpy.context.temp_override(window=window, area=area):
        check(bpy.ops.hairlod.build_lod('EXEC_DEFAULT', guides=32) == {'FINISHED'}, "Build Hair LoD finished")
    preview = lod_preview.preview_of(hair)
    check(preview is not None and hair.hairlod_lod_preview.enabled, "the built hair is previewed")

    hair_draws = []
    draw_levels = lod_preview.LodPreview._draw_levels

    def counted_draw_levels(instance, *args):
        hair_draws.append(time.perf_counter())
        return draw_levels(instance, *args)

    lod_preview.LodPreview._draw_levels = counted_draw_levels
    region_draws = RedrawTimes()

    def after_change(name, change):
        """A step generator: makes `change`, waits for the viewport to come to rest and screenshots it;
        returns (hair draws, region redraws, pixels)."""
        yield from region_draws.at_rest(QUIET)
        hair_draws.clear()
        region_draws.clear()
        change()
        area.tag_redraw()
        yield REDRAW_DELAY
        yield from region_draws.at_rest(QUIET)
        counts = (len(hair_draws), len(region_draws))
        return (*counts, screenshot(window, area, f"preview_redraw_{name}.png"))

    preferences = bpy.context.preferences.system
    anti_aliasing = preferences.viewport_aa
    try:
        def move_view():
            region_3d.view_distance *= 0.97

        def linear(pixels):  # the screen's sRGB values back to linear
            return np.where(pixels <= 0.04045, pixels / 12.92, ((pixels + 0.055) / 1.055) ** 2.4)

        background = yield from harness.background_then_preview(window, area, hair, "preview_redraw_background.png",
                                                                REDRAW_DELAY)
        preferences.viewport_aa = '8'
        drawn, redrawn, smooth = yield from after_change("view", move_view)
        coverage, samples = preview.hair_coverage(region_3d)
        partly = float(np.mean((coverage > 0.0) & (coverage < 1.0)) / max(np.mean(coverage > 0.0), 1e-9))
        check(drawn == samples == 8 and redrawn >= drawn,
              f"after one change of the view the region redraws {redrawn} times (its anti-aliasing) and the hair "
              f"is drawn once in each ({drawn}), {samples} samples")
        check(partly > 0.05, f"the 8 samples cover {100 * partly:.0f} % of the hair's pixels partly")
        drawn, _, again = yield from after_change("unchanged", lambda: None)
        check(drawn == 0 and np.array_equal(again, smooth),
              f"a redraw of the unchanged view draws no hair ({drawn}) and shows the same pixels")

        preferences.viewport_aa = 'OFF'
        drawn, redrawn, single = yield from after_change("one_sample", preview.draw_again)
        coverage, samples = preview.hair_coverage(region_3d)
        check(drawn == 1 and samples == 1 and set(np.unique(coverage).tolist()) <= {0.0, 1.0},
              f"with No Anti-Aliasing the same view is drawn once ({drawn}, {redrawn} redraws), in {samples} "
              f"sample, each pixel hair or not")
        # What the hair adds to the picture, summed in linear light, is the same in 8 samples as in one:
        # the samples spread each strand's light over the pixels it crosses, and each chooses the
        # strands drawn by coverage again (one sample's choice is one draw of that chance: 5 %).
        added = [float((linear(picture) - linear(background)).sum()) for picture in (smooth, single)]
        check(abs(added[0] / added[1] - 1.0) <= 0.05,
              f"the hair's light in 8 samples {added[0] / added[1]:.4f}x that in one sample")

        drawn, redrawn, moved = yield from after_change("view_one_sample", move_view)
        check(drawn == 1, f"with No Anti-Aliasing one change of the view draws the hair once ({drawn}, "
                          f"{redrawn} redraws)")
        drawn, _, forced = yield from after_change("draw_again", preview.draw_again)
        check(drawn == 1 and np.abs(forced - moved).max() <= 1.0 / 255.0,
              f"draw_again draws the hair in full once ({drawn}), the same picture")

        def hair_pixels_differ(before, after):
            return float(np.mean(np.abs(after - before).max(axis=2) > 2.0 / 255.0))

        changes = [
            ("light", lambda: setattr(light.data, "energy", 3.0 * light.data.energy)),
            ("world", lambda: bpy.context.scene.world.node_tree.nodes["Background"].inputs["Color"]
             .default_value.foreach_set((0.6, 0.35, 0.1, 1.0))),
            ("self_shadowing", lambda: setattr(hair.hairlod_lod_preview, "self_shadowing",
                                               0.3 * hair.hairlod_lod_preview.self_shadowing)),
            ("melanin", lambda: setattr(hair.hairlod_lod_preview, "melanin", 0.2)),
            ("object", lambda: setattr(hair, "location", (0.02 * float(np.linalg.norm(upper - lower)), 0.0, 0.0))),
        ]
        before = forced
        for name, change in changes:
            drawn, _, after = yield from after_change(name, change)
            differ = hair_pixels_differ(before, after)
            check(drawn == 1 and differ > 0.002,
                  f"changing the {name} draws the hair again ({drawn}) and changes {100 * differ:.2f} % of the pixels")
            before = after
    finally:
        preferences.viewport_aa = anti_aliasing
        lod_preview.LodPreview._draw_levels = draw_levels
        region_draws.remove()


harness.run(steps)
