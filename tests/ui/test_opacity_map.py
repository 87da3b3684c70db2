"""The LoD preview's deep opacity maps (Blender under Xvfb, see scripts/run_ui_tests.sh). A slab of straight
strands, 6 layers of 251 parallel strands 2 diameters apart (under half a texel of the map) stacked under a
sun straight above:
- the map drawn from the strands holds, averaged over the slab, an optical depth of 2 r / spacing per
  layer above each boundary (hairlod/opacity_map.py: 2 r over the texel's width per strand line), and
  in all the strands' projected area (2 r L each), within 3 %; drawn from the coarsest thick level, the
  same total within 10 %;
- seen from the side, the top layer is lit and the bottom one in shadow, and the Shadowing slider turns
  it off: the mean luminance of the top and bottom thirds of the hair (the sun alone).
Screenshots go to $HAIRLOD_UI_OUT (default out/ui) as opacity_map_*.png.
"""

import math
import os
import sys

import bpy
import numpy as np
from mathutils import Quaternion

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check, screenshot  # noqa: E402

REDRAW_DELAY = 1.0
RADIUS = 0.002
LAYERS, PER_LAYER, POINTS = 6, 251, 9
SPACING_Y, SPACING_Z = 0.004, 0.05


def slab():
    """The strands: along x from -1 to 1, at y = -0.5 .. 0.5 and z = 0, -0.05, ..., -0.25."""
    from hairlod import Strands

    x = np.linspace(-1.0, 1.0, POINTS)
    y = (np.arange(PER_LAYER) - PER_LAYER // 2) * SPACING_Y
    z = -np.arange(LAYERS) * SPACING_Z
    zz, yy = np.meshgrid(z, y, indexing="ij")
    count = zz.size
    points = np.stack([np.broadcast_to(x, (count, POINTS)), np.repeat(yy.reshape(-1, 1), POINTS, axis=1),
                       np.repeat(zz.reshape(-1, 1), POINTS, axis=1)], axis=-1)
    return Strands.from_counts(points.reshape(-1, 3).astype(np.float32), np.full(count, POINTS),
                               np.full(count * POINTS, RADIUS, np.float32))


def linear_luminance(display):
    """Luminance of the scene-linear values behind a screenshot under the Standard view transform
    (the sRGB encoding)."""
    linear = np.where(display <= 0.04045, display / 12.92, ((display + 0.055) / 1.055) ** 2.4)
    return linear @ np.array([0.2126, 0.7152, 0.0722])


def steps():
    import addon_utils

    window = bpy.context.window_manager.windows[0]
    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    from hairlod import opacity_map
    from hairlod.blender.curves import strands_to_curves
    from hairlod.blender.preview import lod_preview
    from hairlod.blender.versions import uses_nodes

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    strands = slab()
    obj = strands_to_curves(strands, "Slab")
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))  # shines straight down (-z)
    sun.data.energy = 3.0
    bpy.context.scene.collection.objects.link(sun)
    # A black world: the sun alone lights the hair.
    world = bpy.context.scene.world
    world.color = (0.0, 0.0, 0.0)
    if uses_nodes(world):
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    check(bpy.ops.hairlod.build_lod(guides=12, levels=3, control_points=8, seed=0) == {'FINISHED'}, "LoD built")
    preview = lod_preview.preview_of(obj)
    settings = obj.hairlod_lod_preview

    area, region_3d = harness.plain_view(next(a for a in window.screen.areas if a.type == 'VIEW_3D'))
    # From the side (looking along -y), orthographic: the layers stacked on screen.
    region_3d.view_perspective = 'ORTHO'
    region_3d.view_rotation = Quaternion((1.0, 0.0, 0.0), math.pi / 2)
    region_3d.view_location = (0.0, 0.0, -0.125)
    region_3d.view_distance = 1.4

    background = yield from harness.background_then_preview(window, area, obj, "opacity_map_background.png",
                                                            REDRAW_DELAY)
    area.tag_redraw()
    yield REDRAW_DELAY
    area.tag_redraw()
    yield REDRAW_DELAY

    # The map from the strands: every texel over the slab holds a line of each layer.
    check(preview.shadow_level == preview.level_count - 1, "the maps are drawn from the strands")
    depth, opacity = preview.opacity.read()
    tile = opacity_map.TILE
    depth, opacity = depth[:, :tile], opacity[:, :tile]
    hair = depth < 1e29
    check(hair.sum() > 1000, f"the light meets the hair on {hair.sum()} texels")
    check(np.allclose(depth[hair], depth[hair].min(), atol=1e-4),
          f"the first hair is the top layer everywhere (depths {depth[hair].min():.4f}-{depth[hair].max():.4f})")
    centre, radius = lod_preview._world_sphere(preview.hair_volume, np.asarray(obj.matrix_world, np.float64))
    pixel = 2.0 * radius / tile
    spacing = opacity_map.layer_spacing(radius)
    per_layer = 2.0 * RADIUS / SPACING_Y
    layer_depths = np.arange(LAYERS) * SPACING_Z
    for index, step in enumerate(opacity_map.LAYER_STEPS):
        above = int(np.sum(layer_depths <= step * spacing))
        measured = float(np.mean(opacity[hair][:, index]))
        check(abs(measured / (above * per_layer) - 1.0) < 0.03,
              f"layer {index} (z0 + {step * spacing:.3f}): mean optical depth {measured:.4f}, {above} layers above "
              f"x {per_layer:.4f}")
    projected = 2.0 * RADIUS * 2.0 * LAYERS * PER_LAYER
    strands_total = float(opacity[..., 3].sum()) * pixel * pixel
    check(abs(strands_total / projected - 1.0) < 0.03,
          f"total optical depth from the strands {strands_total:.4f} x area against their projected area {projected:.4f}")

    lit = screenshot(window, area, "opacity_map_lit.png")
    mask = np.abs(lit - background).max(axis=2) > 0.02
    rows = np.flatnonzero(mask.any(axis=1))
    check(rows.size > 20, f"the hair covers {rows.size} rows")
    third = (rows.max() - rows.min()) / 3.0
    luminance = linear_luminance(lit)

    def bands(image_luminance):
        # Rows run bottom-up (window coordinates): the top layer is at the highest rows.
        top = mask & (np.arange(mask.shape[0])[:, None] >= rows.max() - third)
        bottom = mask & (np.arange(mask.shape[0])[:, None] <= rows.min() + third)
        return float(image_luminance[top].mean()), float(image_luminance[bottom].mean())

    top, bottom = bands(luminance)
    check(top > 2.5 * bottom, f"seen from the side the top layer is lit and the bottom in shadow: {top:.3f} / {bottom:.3f}")

    settings.self_shadowing = 0.0
    area.tag_redraw()
    yield REDRAW_DELAY
    flat = linear_luminance(screenshot(window, area, "opacity_map_unshadowed.png"))
    top0, bottom0 = bands(flat)
    check(top0 < 1.3 * bottom0, f"Shadowing 0: top and bottom alike, {top0:.3f} / {bottom0:.3f}")
    settings.self_shadowing = 1.0

    # Drawn from the coarsest thick level, the maps hold the same strands' optical depth.
    opacity_map.SHADOW_SEGMENTS = 0
    preview.opacity.key = None
    area.tag_redraw()
    yield REDRAW_DELAY
    check(preview.shadow_level == 0, "the maps are drawn from the coarsest thick level")
    depth, opacity = preview.opacity.read()
    thick_total = float(opacity[:, :tile, 3].sum()) * pixel * pixel
    check(abs(thick_total / projected - 1.0) < 0.1,
          f"total optical depth from the thick hairs {thick_total:.4f} x area against the strands' {projected:.4f}")


harness.run(steps)
