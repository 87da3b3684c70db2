"""The LoD preview shades the hair with its Principled Hair material, in the models each Blender has
(Blender under Xvfb, see scripts/run_ui_tests.sh): Chiang everywhere, Huang (Blender 4.x's default)
from Blender 4.0 on. A light and a dark melanin must read as light and dark hair; a Huang material
must change the look from the Chiang material of the same colour as the path tracer says it does: the
ratio of the two mean hair colours in the preview within 20 % per channel of the ratio in path-traced
images of the same hair (the preview shades a Huang material through its Chiang stand-in,
hairlod/bcsdf/chiang_stand_in.h). Screenshots go to $HAIRLOD_UI_OUT (default out/ui) as
lod_material_*.png.
"""

import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check, screenshot  # noqa: E402

REDRAW_DELAY = 1.0
HAS_HUANG = bpy.app.version >= (4, 0, 0)


def steps():
    import addon_utils

    window = bpy.context.window_manager.windows[0]
    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    from hairlod.blender.preview import lod_preview
    from hairlod.blender.principled_hair import new_hair_material, object_hair_params

    strands, obj = harness.generated_hair_object(count=5000, vertices=17, seed=3)
    check(bpy.ops.hairlod.build_lod(guides=48, levels=5, control_points=12, seed=0) == {'FINISHED'}, "LoD built")
    preview = lod_preview.preview_of(obj)
    settings = obj.hairlod_lod_preview
    check(preview is not None and settings.use_material, "the preview is attached and shades with the material")

    area, region_3d = harness.plain_view(next(a for a in window.screen.areas if a.type == 'VIEW_3D'))
    size = float(np.linalg.norm(strands.points.max(axis=0) - strands.points.min(axis=0)))
    region_3d.view_perspective = 'PERSP'
    region_3d.view_location = strands.points.mean(axis=0)
    region_3d.view_distance = 1.5 * size

    background = yield from harness.background_then_preview(window, area, obj, "lod_material_background.png",
                                                            REDRAW_DELAY)

    materials = {"chiang_dark": {"parametrization": "MELANIN", "melanin": 0.6},
                 "chiang_light": {"parametrization": "MELANIN", "melanin": 0.15}}
    if HAS_HUANG:
        materials["chiang_dark"]["model"] = materials["chiang_light"]["model"] = "CHIANG"
        materials["huang_dark"] = {"model": "HUANG", "parametrization": "MELANIN", "melanin": 0.6}
        materials["huang_light"] = {"model": "HUANG", "parametrization": "MELANIN", "melanin": 0.15}
    else:
        print("lod material: Blender", bpy.app.version_string, "has no Huang model; Chiang only")
    colours = {}
    for name, inputs in materials.items():
        material = new_hair_material(name, inputs)
        obj.data.materials.clear()
        obj.data.materials.append(material)
        check(object_hair_params(obj).fibre == name.split("_")[0], f"{name}: the preview's hair is the material's")
        # Two redraws: the preview's first frame after it is turned on is not yet its settled look.
        for _ in range(2):
            area.tag_redraw()
            yield REDRAW_DELAY
        image = screenshot(window, area, f"lod_material_{name}.png")
        mask = np.abs(image - background).max(axis=2) > 0.05
        check(mask.sum() > 500, f"{name}: hair drawn ({mask.sum()} pixels)")
        colours[name] = image[mask].mean(axis=0)
        print(f"lod material {name}: mean hair colour {np.round(colours[name], 3)} over {mask.sum()} pixels")
    for model in ("chiang", "huang") if HAS_HUANG else ("chiang",):
        light, dark = colours[f"{model}_light"], colours[f"{model}_dark"]
        check(light.mean() > 1.3 * dark.mean(), f"{model}: light melanin reads lighter ({light} against {dark})")
    if HAS_HUANG:
        from hairlod import hair_params, render

        for shade in ("dark", "light"):
            traced = {}
            for model in ("chiang", "huang"):
                params = hair_params.from_principled_hair(**materials[f"{model}_{shade}"])
                traced[model] = render.render(strands, "pt", view="mid", width=64, spp=32, params=params, seed=1)["image"]
            hair = np.abs(traced["chiang"] - traced["chiang"][0, 0]).max(axis=2) > 0.003
            expected = traced["huang"][hair].mean(axis=0) / traced["chiang"][hair].mean(axis=0)
            ratio = colours[f"huang_{shade}"] / colours[f"chiang_{shade}"]
            check(np.all(np.abs(ratio / expected - 1.0) < 0.2),
                  f"{shade}: Huang over Chiang of the same colour {np.round(ratio, 3)} in the preview, "
                  f"{np.round(expected, 3)} path-traced")


harness.run(steps)
