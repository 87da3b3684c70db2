"""The viewport LoD preview follows animated hair (Blender under Xvfb, scripts/run_ui_tests.sh).

Two animated hairs get their LoD built and previewed: a hair Curves object of 5,000 strands generated
in examples/data/wavy_cap.hairmesh.json with a Geometry Nodes modifier that tilts it about x
(keyframed: 0 at frame 1, 0.8 rad at frame 10, a nod), and hair on a UV-sphere head that a keyframed
armature nods, the hair following by Deform Curves on Surface (tests/blender/hair_fixtures.py).
Seen from the side, at frames 1 and 10, the preview (every strand drawn,
then the LoD's own levels) must move as Blender's own drawing of the strands moves (the hair pixels'
centroid), share most hair pixels with it, and be closer to it than to the rest pose.
The per-frame cost of following (reading the guides, skinning, uploading the maps) is printed.
Screenshots go to $HAIRLOD_UI_OUT (default out/ui).
"""

import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "blender"))
from harness import REPO_ROOT, check, screenshot  # noqa: E402

HAIR_MESH = os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json")
REDRAW_DELAY = 1.0
ANGLE = 0.8


def view3d(window):
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    return area, area.spaces.active.region_3d


def hair_mask(image, background):
    return np.abs(image - background).max(axis=2) > 0.05


def centroid(mask):
    rows, columns = np.nonzero(mask)
    return np.array([columns.mean(), rows.mean()])


def overlap(a, b):
    """Shared hair pixels over the union, each mask grown by 2 pixels (line widths differ)."""
    def grow(mask):
        grown = mask.copy()
        for axis in (0, 1):
            for shift in (-2, -1, 1, 2):
                grown |= np.roll(mask, shift, axis=axis)
        return grown
    a, b = grow(a), grow(b)
    return float((a & b).sum()) / max(float((a | b).sum()), 1.0)


def follow(window, scene, obj, name, size, view_location, surface=None, rigid=True):
    """Shots at frames 1 and 10 of Blender's own drawing of `obj`, the preview of every strand and the
    LoD, each against a background of its frame without the hair (other objects may move too), seen
    from the side; checks that the preview lies on Blender's drawing and moved with it. `surface`: the
    name of the mesh the strands follow exactly (hair attached to it), where every strand drawn at frame
    10 lies on Blender's drawing as closely as at rest. Not `rigid`: the hair bends and its pixels'
    centroid hardly moves (a sheared scalp: the crown turns, the sides stay), so the shots are compared
    pixel by pixel only."""
    from hairlod.blender.preview import lod_preview

    settings = obj.hairlod_lod_preview
    # Every strand a pixel wide, as Blender draws them: with Strand Coverage the sparse tips keep fewer
    # of their pixels than the dense crown, and the pixels' centroid turns about another point.
    settings.strand_coverage = False
    preview = lod_preview.preview_of(obj)
    area, region_3d = harness.plain_view(view3d(window)[0])
    region_3d.view_perspective = 'ORTHO'
    region_3d.view_rotation = (0.5, 0.5, 0.5, 0.5)  # from the side: the nod turns the image
    region_3d.view_location = view_location
    region_3d.view_distance = 1.6 * size

    def shot(label, preview_on, hidden=False):
        obj.hide_set(hidden)
        settings.enabled = preview_on
        area.tag_redraw()
        yield REDRAW_DELAY
        shots[label] = screenshot(window, area, f"lod_follow_{name}_{label}.png")

    shots = {}
    for frame in (1, 10):
        scene.frame_set(frame)  # frame_change_post: the preview reads the moved guides
        yield from shot(f"background_{frame}", False, hidden=True)
        yield from shot(f"own_{frame}", False)
        settings.width_px = 0.01  # every strand at every control point: the same hair Blender draws
        settings.vertex_tolerance_px = 0.0
        yield from shot(f"strands_{frame}", True)
        settings.width_px = 2.0
        settings.property_unset("vertex_tolerance_px")
        yield from shot(f"lod_{frame}", True)
    check(preview.follow_status == "", f"{name}: following the hair ({preview.follow_status or 'no message'})")
    check(preview.guides is not None, f"{name}: the preview drew the moved guides")
    print(f"{name}, following per frame: " + ", ".join(f"{k} {v:.2f} ms" for k, v in preview.follow_stats.items()
                                                      if k.endswith("_ms")))
    expected = f"Strands follow the surface '{surface}'" if surface else None
    check(preview.follow_stats.get("surface") == expected, f"{name}: {preview.follow_stats.get('surface')}")

    masks = {label: hair_mask(image, shots[f"background_{label.rsplit('_', 1)[1]}"])
             for label, image in shots.items() if not label.startswith("background")}
    for label, mask in masks.items():
        check(mask.sum() > 200, f"{name}, {label}: hair pixels drawn ({mask.sum()})")
    own_motion = centroid(masks["own_10"]) - centroid(masks["own_1"])
    moved = float(np.linalg.norm(own_motion))
    if rigid:
        check(moved > 20.0, f"{name}: Blender's own drawing moved {moved:.0f} px between frames 1 and 10")
    own_change = 1.0 - overlap(masks["own_10"], masks["own_1"])
    check(own_change > 0.3, f"{name}: {own_change:.0%} of Blender's own hair pixels changed between frames 1 and 10")
    for kind in ("strands", "lod"):
        # The preview moves as Blender's drawing moves (whatever the two drawings' own difference).
        motion = centroid(masks[f"{kind}_10"]) - centroid(masks[f"{kind}_1"])
        miss = float(np.linalg.norm(motion - own_motion))
        if rigid:
            check(miss < 0.15 * moved, f"{name}, {kind}: moved {np.linalg.norm(motion):.0f} px, {miss:.1f} px from "
                                       f"Blender's own drawing's motion of {moved:.0f} px")
        shared = {frame: overlap(masks[f"{kind}_{frame}"], masks[f"own_{frame}"]) for frame in (1, 10)}
        for frame in (1, 10):
            check(shared[frame] > 0.5, f"{name}, frame {frame}, {kind}: {shared[frame]:.0%} of hair pixels shared with Blender's own")
        if surface and kind == "strands":
            # Within the pixels' own noise of how each Blender draws lines: tests/blender/test_lod_follow.py
            # asserts the strands' points to 1e-5 of the hair's size. The rigid turn read 75.5 % against
            # 75.9 % in Blender 3.4 and 74.1 % against 75.7-76.1 % in Blender 5.2.
            check(shared[10] > shared[1] - 0.03, f"{name}, strands: {shared[10]:.1%} of hair pixels shared with Blender's "
                                                 f"own at frame 10, {shared[1]:.1%} at rest")
        stale = overlap(masks[f"{kind}_10"], masks["own_1"])
        print(f"{name}, {kind}: shared with Blender's own at frame 10 {shared[10]:.1%}, at rest {shared[1]:.1%}, "
              f"with its rest pose {stale:.1%}")
        check(overlap(masks[f"{kind}_10"], masks["own_10"]) > stale + 0.1,
              f"{name}, frame 10, {kind}: closer to the moved hair than to the rest pose (shared with rest {stale:.0%})")


def steps():
    import addon_utils

    window = bpy.context.window_manager.windows[0]
    check(addon_utils.enable("hairlod", default_set=True) is not None, "add-on enabled")
    # One sample of each drawing (No Anti-Aliasing): the shots compare where lines lie, pixel by pixel,
    # and a shot taken while the viewport still adds samples would mix two of them.
    bpy.context.preferences.system.viewport_aa = 'OFF'
    import hairlod
    from hairlod import hairmesh
    from hairlod.blender.curves import strands_to_curves
    from hairlod.blender.packed_asset import packed_asset
    from hairlod.blender.preview import lod_preview
    from hair_fixtures import add_keyframed_rotation, build_scene  # tests/blender/hair_fixtures.py

    # Geometry Nodes: a keyframed Transform nods generated hair.
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    scene = bpy.context.scene
    scene.frame_set(1)
    strands = hairlod.generate_strands(hairmesh.read(HAIR_MESH), count=5000, vertices=17, seed=2)
    obj = strands_to_curves(strands, "Hair")
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    add_keyframed_rotation(obj, ((1, (0.0, 0.0, 0.0)), (10, (ANGLE, 0.0, 0.0))))
    check(bpy.ops.hairlod.build_lod(guides=48, levels=5, control_points=12, seed=0) == {'FINISHED'}, "LoD built")
    check(lod_preview.preview_of(obj) is not None and packed_asset(obj) is not None, "the preview is attached")
    size = float(np.linalg.norm(strands.points.max(axis=0) - strands.points.min(axis=0)))
    yield from follow(window, scene, obj, "nodes", size, (0.0, 0.0, 0.0))

    # An armature turns a head; the hair on it follows by Deform Curves on Surface.
    for existing in list(bpy.data.objects):
        bpy.data.objects.remove(existing)
    scene.frame_set(1)
    # Rigidly, then with the scalp sheared (the crown turns, the sides stay: Blender turns each strand
    # with its own root triangle).
    for rigid in (True, False):
        for existing in list(bpy.data.objects):
            bpy.data.objects.remove(existing)
        scene.frame_set(1)
        hair, rig = build_scene(rigid=rigid)
        bone = rig.pose.bones["head"]
        bone.rotation_mode = 'XYZ'
        for frame, angle in ((1, 0.0), (10, ANGLE)):
            bone.rotation_euler = (angle, 0.0, 0.3 * angle)
            bone.keyframe_insert("rotation_euler", frame=frame)
        scene.frame_set(1)
        bpy.context.view_layer.objects.active = hair
        hair.select_set(True)
        check(bpy.ops.hairlod.build_lod(guides=32, levels=4, control_points=8, seed=0) == {'FINISHED'},
              "LoD of the hair on the head built")
        yield from follow(window, scene, hair, "surface" if rigid else "sheared", 4.0, (0.0, 0.0, 0.0), surface="Head",
                          rigid=rigid)


harness.run(steps)
