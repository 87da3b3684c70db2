"""The LoD preview follows deformed hair: the guides it reads from the evaluated Curves (a Geometry
Nodes modifier here, keyframed), headless. Drawing is tested under Xvfb (tests/ui)."""

import math

import bpy
import numpy as np
import pytest

from hairlod.blender.curves import curves_to_strands, evaluated_curve_subset, new_geometry_node_tree, strands_to_curves
from hairlod.blender.lod_build_job import COLLECTION_NAME
from hairlod.blender.packed_asset import packed_asset
from hairlod.blender.preview import lod_preview
from hair_fixtures import add_keyframed_rotation, build_scene, hanging_hair, node_input, turn_head

pytestmark = pytest.mark.usefixtures("addon")

ANGLE = 0.6  # radians about z at frame 10


def rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def add_keyframed_turn(obj):
    """The hair turns about z: 0 at frame 1, ANGLE at frame 10."""
    return add_keyframed_rotation(obj, ((1, (0.0, 0.0, 0.0)), (10, (0.0, 0.0, ANGLE))))


@pytest.fixture
def built_hair():
    scene = bpy.context.scene
    scene.frame_set(1)
    obj = strands_to_curves(hanging_hair(), "Hair")
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    # In background mode Build Hair LoD attaches no preview (nothing draws): attach it as the UI does.
    lod_preview.attach(obj, packed_asset(obj), packed=True)
    yield obj
    scene.frame_set(1)
    collection = bpy.data.collections.get(COLLECTION_NAME)
    if collection is not None:
        bpy.data.collections.remove(collection)
    lod_preview.detach(obj.name)
    bpy.data.objects.remove(obj)


def test_the_preview_reads_the_guides_of_the_animated_hair(built_hair):
    obj = built_hair
    asset = packed_asset(obj)
    preview = lod_preview.preview_of(obj)
    assert preview is not None and preview.guides is None and preview.pending_guides is None
    add_keyframed_turn(obj)
    scene = bpy.context.scene
    scene.frame_set(10)
    lod_preview._on_frame_change(scene, bpy.context.evaluated_depsgraph_get())
    assert preview.follow_status == ""
    size = float(np.ptp(asset.rest_guides.reshape(-1, 3), axis=0).max())
    expected = asset.rest_guides @ rotation_z(ANGLE).T
    # Rigid motion: the guides read and resampled are the turned rest guides to float precision.
    assert np.abs(preview.pending_guides - expected).max() <= 1e-5 * size
    assert preview.follow_stats["read_ms"] >= 0.0

    # Back at frame 1 the hair is at rest again; frame 1 again reads nothing new.
    scene.frame_set(1)
    lod_preview._on_frame_change(scene, bpy.context.evaluated_depsgraph_get())
    assert np.abs(preview.pending_guides - asset.rest_guides).max() <= 1e-5 * size
    assert not preview.read_guides(obj, bpy.context.evaluated_depsgraph_get())


def test_turning_the_preview_on_catches_up_with_the_current_frame(built_hair):
    """While the preview is off its handlers read nothing; turned on, it reads the hair as it is now."""
    obj = built_hair
    asset = packed_asset(obj)
    preview = lod_preview.preview_of(obj)
    obj.hairlod_lod_preview.enabled = False
    add_keyframed_turn(obj)
    scene = bpy.context.scene
    scene.frame_set(10)
    lod_preview._on_frame_change(scene, bpy.context.evaluated_depsgraph_get())
    assert preview.pending_guides is None  # off: nothing read
    obj.hairlod_lod_preview.enabled = True
    size = float(np.ptp(asset.rest_guides.reshape(-1, 3), axis=0).max())
    assert np.abs(preview.pending_guides - asset.rest_guides @ rotation_z(ANGLE).T).max() <= 1e-5 * size


def test_only_the_guide_curves_are_gathered(built_hair):
    obj = built_hair
    asset = packed_asset(obj)
    subset = evaluated_curve_subset(obj, asset.guide_strands, bpy.context.evaluated_depsgraph_get(), asset.strand_count)
    assert len(subset.offsets) - 1 == asset.guide_count
    whole = hanging_hair()
    expected = np.concatenate([whole.points[whole.offsets[g]:whole.offsets[g + 1]] for g in asset.guide_strands])
    assert np.array_equal(subset.points, expected)


def test_a_changed_topology_stops_following_and_says_why(built_hair):
    obj = built_hair
    preview = lod_preview.preview_of(obj)
    tree = new_geometry_node_tree("Delete")
    group_in, group_out = tree.nodes.new('NodeGroupInput'), tree.nodes.new('NodeGroupOutput')
    delete = tree.nodes.new('GeometryNodeDeleteGeometry')
    delete.domain = 'CURVE'
    index, compare = tree.nodes.new('GeometryNodeInputIndex'), tree.nodes.new('FunctionNodeCompare')
    compare.data_type, compare.operation = 'INT', 'LESS_THAN'
    node_input(compare, "B").default_value = 10  # curves 0-9 go
    tree.links.new(index.outputs[0], node_input(compare, "A"))
    tree.links.new(group_in.outputs[0], delete.inputs["Geometry"])
    tree.links.new(compare.outputs[0], delete.inputs["Selection"])
    tree.links.new(delete.outputs["Geometry"], group_out.inputs[0])
    obj.modifiers.new("Delete", 'NODES').node_group = tree
    assert not preview.read_guides(obj, bpy.context.evaluated_depsgraph_get())
    assert "590 curves now, 600 when the LoD was built" in preview.follow_status


@pytest.mark.parametrize("rigid", [True, False], ids=["rigid head turn", "bent scalp"])
def test_skinning_follows_deform_curves_on_surface(rigid, empty_scene):
    """Against Blender's own deformation of every strand (Deform Curves on Surface on an armature-
    animated head): a rigid head turn is reproduced to float precision. A non-rigid one (the scalp
    sheared by the weights) is followed to a fraction of the motion and reported: Blender turns each
    curve with its root triangle's frame, which a sheared mesh turns differently from its neighbours,
    and skinning from guides is smooth across a cluster."""
    from hairlod import lod

    hair, rig = build_scene(rigid)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    rest = curves_to_strands(hair, depsgraph=depsgraph)
    asset = lod.build_lod(rest, guides=32, levels=4, control_points=8, seed=2)
    rest_skin = asset.skin(asset.rest_guides)["strands"].points
    size = float(np.linalg.norm(np.ptp(rest_skin, axis=0)))
    radius = float(np.median(rest.radius))

    turn_head(rig, 0.5)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    moved = curves_to_strands(hair, depsgraph=depsgraph)
    assert np.abs(moved.points - rest.points).max() > 0.1 * size  # Blender moved the hair
    guides = asset.resample_guides(evaluated_curve_subset(hair, asset.guide_strands, depsgraph, asset.strand_count))
    skinned = asset.skin(guides)["strands"].points
    truth = moved.resampled(8, lod.LOD_ARC_LENGTH_SUBDIVISIONS).points
    at_rest = lod.following_error(rest_skin, rest.resampled(8, lod.LOD_ARC_LENGTH_SUBDIVISIONS).points, radius, size)
    error = lod.following_error(skinned, truth, radius, size)
    stale = lod.following_error(rest_skin, truth, radius, size)  # a preview left at the rest pose
    print(f"{'rigid' if rigid else 'bent'}: {asset.strand_count} strands, {asset.guide_count} guides; following error "
          + ", ".join(f"{k} {v:.3g}" for k, v in error.items()) + f"; at rest max {at_rest['max_of_size']:.2g} of size; not following: mean {stale['mean_of_size']:.3g}, "
          f"p99 {stale['p99_of_size']:.3g} of size")
    if rigid:
        # The rest pose's quantisation error moved rigidly, plus float rounding.
        assert error["max_of_size"] <= at_rest["max_of_size"] + 1e-5
    else:
        assert error["p99_of_size"] <= stale["p99_of_size"] / 2.5 and error["mean_of_size"] <= stale["mean_of_size"] / 4
    # The thick hairs skinned by the maps against the strands Blender deformed: the share of those
    # strands passing through their hair's sections (thick_hair_check.strands_through_sections).
    from hairlod.thick_hair_check import strands_through_sections

    def through(geometry, points):
        return [strands_through_sections(g["centres"], g["major"], g["minor"], level.membership,
                                         points.reshape(asset.strand_count, asset.control_points, 3))
                for level, g in zip(asset.levels, geometry["levels"])]

    held_at_rest = through(asset.skin(asset.rest_guides), rest.resampled(8, lod.LOD_ARC_LENGTH_SUBDIVISIONS).points)
    held = through(asset.skin(guides), truth)
    print(f"{'rigid' if rigid else 'bent'}: deformed strands through their thick hairs' sections "
          + " / ".join(f"{h:.2f}" for h in held) + " (at rest " + " / ".join(f"{h:.2f}" for h in held_at_rest) + ")")
    for at_rest, moved in zip(held_at_rest, held):
        assert moved >= at_rest - (0.01 if rigid else 0.5)


@pytest.mark.parametrize("rigid, subdivided", [(True, False), (False, False), (False, True)],
                         ids=["rigid head turn", "sheared scalp", "sheared subdivided scalp"])
def test_the_preview_moves_strands_with_their_surface(rigid, subdivided, empty_scene):
    """Hair attached to an armature-animated head: the preview's strands turn with their root
    triangles as Blender's Deform Curves on Surface turns them, to float precision also where the
    scalp shears (where skinning from guides is off by over a hundred strand radii), and where a
    Subdivision Surface on the head makes the mesh the node finds the roots on (the preview binds to
    it at the pose the LoD was built at)."""
    from hairlod import lod, surface_attachment

    hair, rig = build_scene(rigid)
    if subdivided:
        bpy.data.objects["Head"].modifiers.new("Subdivision", 'SUBSURF').levels = 1
        bpy.context.view_layer.objects.active = hair
    assert bpy.ops.hairlod.build_lod(guides=32, levels=4, control_points=8, seed=2) == {'FINISHED'}
    lod_preview.attach(hair, packed_asset(hair), packed=True)
    preview = lod_preview.preview_of(hair)
    asset = preview.asset
    depsgraph = bpy.context.evaluated_depsgraph_get()
    rest = asset.preview_vertices()["strands"]["position"].reshape(asset.strand_count, asset.control_points, 3)
    size = float(np.linalg.norm(np.ptp(rest.reshape(-1, 3), axis=0)))
    radius = float(np.median(curves_to_strands(hair, depsgraph=depsgraph).radius))
    assert not preview.read_guides(hair, depsgraph)  # at rest: nothing to skin, but bound
    assert preview.surface

    turn_head(rig, 0.5)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    assert preview.read_guides(hair, depsgraph)
    assert preview.pending_surface is not None, preview.follow_stats.get("surface")
    assert preview.follow_stats["surface"] == "Strands follow the surface 'Head'"
    truth = curves_to_strands(hair, depsgraph=depsgraph).resampled(asset.control_points, lod.LOD_ARC_LENGTH_SUBDIVISIONS)
    truth = truth.points.reshape(asset.strand_count, asset.control_points, 3)[asset.strand_order]
    assert np.abs(truth - rest).max() > 0.1 * size  # the hair moved
    # Laid out for the texture: whole rows of strands, the first strand_count of them the strands'.
    assert len(preview.pending_surface) == lod_preview.surface_rows(asset.strand_count)
    moved = surface_attachment.apply(preview.pending_surface[:asset.strand_count], rest)
    distance = np.linalg.norm(moved - truth, axis=-1)
    print(f"{'rigid' if rigid else 'sheared'}{', subdivided' if subdivided else ''}: surface following max {distance.max() / size:.2g} of the size, "
          f"p99 {np.percentile(distance, 99) / radius:.2g} strand radii")
    assert distance.max() <= 1e-5 * size

    # The next pose is written beside the transforms drawn (what _apply_pending_guides hands the
    # texture, done here without a GPU), never over them: a rebuild of the buffers uploads them again.
    drawn = preview.surface_transforms = preview.pending_surface
    drawn_values, preview.pending_surface = drawn.copy(), None
    turn_head(rig, 0.3)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    assert preview.read_guides(hair, depsgraph)
    assert preview.pending_surface is not None and not np.shares_memory(preview.pending_surface, drawn)
    np.testing.assert_array_equal(drawn, drawn_values)
    truth = curves_to_strands(hair, depsgraph=depsgraph).resampled(asset.control_points, lod.LOD_ARC_LENGTH_SUBDIVISIONS)
    truth = truth.points.reshape(asset.strand_count, asset.control_points, 3)[asset.strand_order]
    moved = surface_attachment.apply(preview.pending_surface[:asset.strand_count], rest)
    assert np.linalg.norm(moved - truth, axis=-1).max() <= 1e-5 * size

    # Something else moves the hair too (a Geometry Nodes offset after the node): the strands go back
    # to following the guides, and the panel says why.
    tree = new_geometry_node_tree("Lift")
    group_in, group_out = tree.nodes.new('NodeGroupInput'), tree.nodes.new('NodeGroupOutput')
    lift = tree.nodes.new('GeometryNodeSetPosition')
    lift.inputs["Offset"].default_value = (0.0, 0.0, 0.05)
    tree.links.new(group_in.outputs[0], lift.inputs["Geometry"])
    tree.links.new(lift.outputs["Geometry"], group_out.inputs[0])
    hair.modifiers.new("Lift", 'NODES').node_group = tree
    assert preview.read_guides(hair, bpy.context.evaluated_depsgraph_get())
    assert preview.pending_surface is None
    assert preview.follow_stats["surface"].startswith("Strands follow the guides (the hair moves otherwise than its surface")
    lod_preview.detach(hair.name)


def test_a_subdivided_surface_is_bound_only_at_the_pose_the_lod_was_built_at(empty_scene):
    """Where the surface's modifiers change its mesh (a Subdivision Surface), the strands are bound to the
    mesh they make, which takes the hair at its build pose: attached elsewhere (a file reopened at
    another frame), the strands follow the guides, and say so, until the hair is back there."""
    hair, rig = build_scene(False)
    bpy.data.objects["Head"].modifiers.new("Subdivision", 'SUBSURF').levels = 1
    bpy.context.view_layer.objects.active = hair
    assert bpy.ops.hairlod.build_lod(guides=32, levels=4, control_points=8, seed=2) == {'FINISHED'}
    turn_head(rig, 0.5)
    lod_preview.attach(hair, packed_asset(hair), packed=True)  # reads the hair as it is now
    preview = lod_preview.preview_of(hair)
    assert preview.pending_guides is not None
    assert preview.surface is None and preview.pending_surface is None
    assert preview.follow_stats["surface"] == ("Strands follow the guides until the hair is back at the pose the LoD "
                                               "was built at (the modifiers of 'Head' change its mesh)")
    turn_head(rig, 0.0)
    assert preview.read_guides(hair, bpy.context.evaluated_depsgraph_get())  # back at rest: a change of pose
    assert preview.surface
    turn_head(rig, 0.3)
    assert preview.read_guides(hair, bpy.context.evaluated_depsgraph_get())
    assert preview.pending_surface is not None
    assert preview.follow_stats["surface"] == "Strands follow the surface 'Head'"
    lod_preview.detach(hair.name)


def test_unattached_hair_follows_the_guides(built_hair):
    preview = lod_preview.preview_of(built_hair)
    add_keyframed_turn(built_hair)
    bpy.context.scene.frame_set(10)
    assert preview.read_guides(built_hair, bpy.context.evaluated_depsgraph_get())
    assert preview.pending_surface is None and preview.surface is False


def test_headless_export_stores_the_guides_of_a_frame_range(built_hair, tmp_path):
    """pipeline.export_lod(frames=...): what a `blender -b` script exports for an engine."""
    from hairlod import lod
    from hairlod.blender import pipeline

    obj = built_hair
    add_keyframed_turn(obj)
    scene = bpy.context.scene
    scene.frame_set(4)
    calls = []
    summary = pipeline.export_lod(obj, tmp_path / "export", bake=False, frames=range(1, 11),
                                  progress=lambda done, total: calls.append((done, total)))
    assert summary["frames"] == 10 and calls[-1] == (10, 10)
    assert scene.frame_current == 4  # the scene is back where it was
    asset = lod.load(tmp_path / "export" / "lod")
    frames, guides = lod.load_animation(tmp_path / "export" / "lod", asset)
    assert frames.tolist() == list(range(1, 11))
    size = float(np.ptp(asset.rest_guides.reshape(-1, 3), axis=0).max())
    for frame, pose in zip(frames, guides):
        angle = ANGLE * (frame - 1) / 9  # the keyframes are linear
        assert np.abs(pose - asset.rest_guides @ rotation_z(angle).T).max() <= 1e-5 * size, f"frame {frame}"


def test_export_of_a_frame_range_refuses_a_changing_topology(built_hair, tmp_path):
    from hairlod.blender import pipeline

    obj = built_hair
    tree = new_geometry_node_tree("Delete later")
    group_in, group_out = tree.nodes.new('NodeGroupInput'), tree.nodes.new('NodeGroupOutput')
    delete = tree.nodes.new('GeometryNodeDeleteGeometry')
    delete.domain = 'CURVE'
    tree.links.new(group_in.outputs[0], delete.inputs["Geometry"])
    tree.links.new(delete.outputs["Geometry"], group_out.inputs[0])
    selection = delete.inputs["Selection"]
    for frame, value in ((1, False), (3, True)):  # from frame 3 every curve is deleted
        selection.default_value = value
        selection.keyframe_insert("default_value", frame=frame)
    obj.modifiers.new("Delete later", 'NODES').node_group = tree
    with pytest.raises(ValueError, match=r"frame 3: 'Hair[.0-9]*' has 0 curves now, 600 when the LoD was built"):
        pipeline.export_lod(obj, tmp_path / "export", bake=False, frames=range(1, 5))
    assert not (tmp_path / "export" / "lod").exists()
